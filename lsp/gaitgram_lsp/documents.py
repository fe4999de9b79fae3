"""Open documents, and their analyses by version: the server's only state.

Edits are applied as they arrive; the analysis (parse + ``check``) runs debounced, in one
worker thread, one at a time, incrementally (``gaitgram.language.incremental``). Its result, a
:class:`Snapshot`, belongs to one revision of the text. It is published only if that is
still the document's revision when it is ready, and features read it only while it is:

* ``await documents.current(uri)`` gives the snapshot of the current text, analysing it now
  if it is not ready yet, or ``None`` if the text changed meanwhile (the request is stale);
* completion does not wait (but for a document's first analysis): it reads the last built
  :class:`CompletionModel`, which holds only plain values, together with the current text.
  The model is built after the diagnostics are published, in the same worker.

Why a snapshot is not read once its revision is not the current one: its offsets are those of
an older text, so an answer from it would point at the wrong place in the editor. (The
snapshot itself never changes: the incremental parser builds new objects for what moved.)
"""

from __future__ import annotations

import asyncio
import functools
import gc
import itertools
import json
import logging
import os
from collections.abc import Callable, Iterable, Mapping
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from functools import cached_property

from lsprotocol import types

from gaitgram.analysis import CheckResult, check
from gaitgram.collector import gc_paused
from gaitgram.ide.workspace import WorkspaceGrammars, grammar_files
from gaitgram.language import parse
from gaitgram.language.incremental import IncrementalParser, Stale
from gaitgram.language.source import MAX_SOURCE_BYTES, SourceText
from gaitgram_lsp.features.completion import CompletionModel
from gaitgram_lsp.features.diagnostics import SOURCE, WireCache, WireDiagnostic, to_lsp
from gaitgram_lsp.positions import UTF16, ClientText, PositionIndex

log = logging.getLogger(__name__)
_result_ids = itertools.count(1)

#: Edits closer together than this are analysed once, for the last of them.
DEBOUNCE_SECONDS = 0.03
#: After this long without an analysis, the garbage collector looks at everything once.
IDLE_COLLECT_SECONDS = 5.0
#: Set to compare every incremental parse with a full one (slow; for tests and bug hunts).
VERIFY_ENV = "GAITGRAM_LSP_VERIFY"
#: Documents analysed at the same time (each in its own worker thread).
WORKERS = 4


def too_large(text: str) -> str | None:
    """Why ``text`` is not analysed, if it is larger than ``gaitgram check`` reads a grammar."""
    if len(text) * 4 <= MAX_SOURCE_BYTES:  # no character takes more than 4 bytes
        return None
    size = len(text.encode("utf-8", "surrogatepass"))
    if size <= MAX_SOURCE_BYTES:
        return None
    return (
        f"this document is {size / 1e6:.1f} MB; grammars over {MAX_SOURCE_BYTES / 1e6:.1f} MB are not "
        "analysed (gaitgram check refuses them too): split it into smaller files"
    )


@dataclass(eq=False)
class Snapshot:
    """One analysed revision of a document: the model, its facts and diagnostics."""

    uri: str
    version: int | None  # the client's
    revision: int  # ours: counts every change, so stale results are recognised
    result: CheckResult
    positions: PositionIndex
    wire_diagnostics: list[WireDiagnostic]
    #: Names this result for pull diagnostics (``previousResultId``).
    result_id: str = field(default_factory=lambda: str(next(_result_ids)))
    #: The text was too large to analyse: ``result`` is of no text, and requests get nothing.
    refused: bool = False
    #: Each of ``wire_diagnostics`` as JSON, when it was made with them (``WireCache``).
    encoded: list[str] | None = None

    @cached_property
    def diagnostics(self) -> list[types.Diagnostic]:
        return to_lsp(self.wire_diagnostics)

    @cached_property
    def published_params(self) -> str:
        """``publishDiagnostics`` parameters as JSON: encoded in the analysis thread, so the
        event loop only writes them (thousands of diagnostics take tens of milliseconds)."""
        if self.encoded is None:
            params = {"uri": self.uri, "diagnostics": self.wire_diagnostics}
            if self.version is not None:
                params["version"] = self.version
            return json.dumps(params, separators=(",", ":"))
        version = "" if self.version is None else f',"version":{self.version}'
        return f'{{"uri":{json.dumps(self.uri)},"diagnostics":[{",".join(self.encoded)}]{version}}}'

    @cached_property
    def completion(self) -> CompletionModel:
        return CompletionModel.of(self.result)

    @property
    def source(self) -> SourceText:
        return self.result.grammar.source

    @property
    def text(self) -> str:
        return self.result.grammar.source.text


def analyse(
    text: str,
    *,
    uri: str = "file:///untitled.gg",
    version: int | None = None,
    revision: int = 0,
    encoding: str = UTF16,
    parser: IncrementalParser | None = None,
    defines: Mapping[str, int] | None = None,
    stop: Callable[[], bool] | None = None,
    wire: WireCache | None = None,
) -> Snapshot:
    """Parse and check ``text``: what ``gaitgram check`` does, reusing ``parser``'s work.
    ``stop`` is asked between the parts of the work: once it says yes, :class:`Stale` is raised
    (the text has changed, and the rest would be of no use)."""
    stale = stop or (lambda: False)
    source = SourceText(text)
    if parser is None:
        grammar = parse(source, defines=defines)
    else:
        try:
            grammar = parser.parse(source, stale)
        except Stale:
            raise
        except Exception:  # a bug in the incremental path must cost speed, never answers
            log.exception("incremental parse failed; parsing the whole document")
            parser.reset()
            grammar = parse(source, defines=parser.external_defines)
    if stale():
        raise Stale
    result = check(grammar)
    if stale():
        raise Stale
    positions = PositionIndex(source, encoding)
    made, encoded = (wire or WireCache()).encode(result, positions)
    return Snapshot(
        uri=uri,
        version=version,
        revision=revision,
        result=result,
        positions=positions,
        wire_diagnostics=made,
        encoded=encoded,
    )


@dataclass(eq=False)
class Document:
    """The client's text of one document, and where its analysis stands."""

    uri: str
    client: ClientText
    version: int | None
    revision: int = 0
    parser: IncrementalParser = field(default_factory=IncrementalParser)
    #: Its diagnostics as sent last, for the next analysis to reuse.
    wire: WireCache = field(default_factory=WireCache)
    #: The last finished analysis, of this or an earlier revision.
    snapshot: Snapshot | None = None
    #: What completion offers: from the last analysis whose model is built. Completion
    #: reads it without waiting, so it may be an analysis behind.
    completion: CompletionModel | None = None
    _waiters: list[tuple[int, asyncio.Future[Snapshot | None]]] = field(default_factory=list)
    _timer: asyncio.TimerHandle | None = None
    _task: asyncio.Task[None] | None = None

    @property
    def text(self) -> str:
        return self.client.text

    @property
    def current(self) -> Snapshot | None:
        """The snapshot of the current text, if it is ready."""
        snapshot = self.snapshot
        return snapshot if snapshot is not None and snapshot.revision == self.revision else None

    def line(self, number: int) -> str:
        """A line of the current text (``""`` past the end), for a cheap look at the cursor."""
        return self.client.line(number)


class Documents:
    """The open documents of one client, analysed in the background."""

    def __init__(
        self,
        on_analysed: Callable[[Snapshot], None] = lambda snapshot: None,
        *,
        debounce: float = DEBOUNCE_SECONDS,
    ) -> None:
        self.on_analysed = on_analysed
        self.debounce = debounce
        self.encoding: str = UTF16
        self.defines: dict[str, int] = {}
        self._open: dict[str, Document] = {}
        # One document's analyses run one after another (``Document._task``); several documents'
        # run side by side, so a large one does not hold up the analysis of the others.
        self._executor = ThreadPoolExecutor(max_workers=WORKERS, thread_name_prefix="gaitgram-analysis")
        self._idle: asyncio.TimerHandle | None = None

    # ---- the client's notifications ---------------------------------------------------

    def open(self, uri: str, text: str, version: int | None) -> None:
        self.close(uri)
        parser = IncrementalParser(self.defines, verify=bool(os.environ.get(VERIFY_ENV)))
        document = Document(uri, ClientText.of(text), version, parser=parser)
        self._open[uri] = document
        self._start(document)  # nothing to debounce: the user is looking at it now

    def change(
        self, uri: str, version: int | None, changes: Iterable[types.TextDocumentContentChangeEvent]
    ) -> None:
        document = self._open.get(uri)
        if document is None:
            return
        for change in changes:
            if isinstance(change, types.TextDocumentContentChangePartial):
                document.client.apply(change.range, change.text, self.encoding)
            else:
                document.client = ClientText.of(change.text)
        document.version = version
        document.revision += 1
        self._resolve(document, None)  # requests about older text are stale now
        if document._timer is not None:
            document._timer.cancel()
        document._timer = asyncio.get_running_loop().call_later(self.debounce, self._start, document)

    def close(self, uri: str) -> None:
        document = self._open.pop(uri, None)
        if document is not None:
            if document._timer is not None:
                document._timer.cancel()
            document.revision += 1
            self._resolve(document, None)

    # ---- reading ---------------------------------------------------------------------------

    def get(self, uri: str) -> Document | None:
        return self._open.get(uri)

    def __iter__(self):
        return iter(list(self._open.values()))

    async def current(self, uri: str) -> Snapshot | None:
        """The snapshot of the current text, analysed now if need be; ``None`` if the
        document is not open or changed before its analysis finished."""
        document = self._open.get(uri)
        if document is None:
            return None
        if (ready := document.current) is not None:
            return ready
        future: asyncio.Future[Snapshot | None] = asyncio.get_running_loop().create_future()
        document._waiters.append((document.revision, future))
        self._start(document)  # a reader is waiting: no more debouncing
        snapshot = await future
        return snapshot if snapshot is not None and document.current is snapshot else None

    # ---- analysis ----------------------------------------------------------------------------

    def _start(self, document: Document) -> None:
        if document._timer is not None:
            document._timer.cancel()
            document._timer = None
        if document._task is None or document._task.done():
            document._task = asyncio.get_running_loop().create_task(self._analyse(document))

    async def _analyse(self, document: Document) -> None:
        """Analyse until the snapshot is of the current text (edits may arrive meanwhile)."""
        loop = asyncio.get_running_loop()
        while self._open.get(document.uri) is document and document.current is None:
            if document._timer is not None:  # an edit is still being debounced: its timer restarts us
                return
            work = functools.partial(
                self._work, loop, document, document.text, document.version, document.revision
            )
            try:
                await loop.run_in_executor(self._executor, work)
            except Exception:
                log.exception("analysis of %s failed", document.uri)
                self._resolve(document, None)
                return

    def _work(
        self,
        loop: asyncio.AbstractEventLoop,
        document: Document,
        text: str,
        version: int | None,
        revision: int,
    ) -> None:
        """In the worker: analyse and encode, hand the snapshot over, then build what can wait.

        The collector is paused throughout and what the analysis made is then frozen (left
        to reference counting): a large grammar's model is a million small objects, and
        the collector's passes over them, in this thread or in the event loop's, took
        longer than the analysis. What is frozen is looked at again when the server is
        idle (:meth:`collect`)."""

        def stale() -> bool:  # read across threads: an int and a dict look-up, atomic
            return document.revision != revision or self._open.get(document.uri) is not document

        with gc_paused():
            refusal = too_large(text)
            if refusal is not None:
                snapshot = refused(document.uri, version, revision, refusal)
            else:
                try:
                    snapshot = analyse(
                        text,
                        uri=document.uri,
                        version=version,
                        revision=revision,
                        encoding=self.encoding,
                        parser=document.parser,
                        stop=stale,
                        wire=document.wire,
                    )
                except Stale:  # the text changed meanwhile: the next analysis is on its way
                    return
            snapshot.published_params  # noqa: B018  (cached: encoded here, off the loop)
            if document.completion is None:  # the first analysis: completion is waiting for it
                document.completion = snapshot.completion
            gc.freeze()
        loop.call_soon_threadsafe(self._deliver, document, snapshot)
        if stale():  # edits came meanwhile: the next analysis builds these, for its own text
            return
        with gc_paused():  # once the diagnostics are out: what requests read
            document.completion = snapshot.completion
            snapshot.result.facts.recursive  # noqa: B018  (cached: hover shows it)
            gc.freeze()

    def _deliver(self, document: Document, snapshot: Snapshot) -> None:
        """On the loop: keep the snapshot, and publish it if its text is still current."""
        if self._idle is not None:
            self._idle.cancel()
        self._idle = asyncio.get_running_loop().call_later(IDLE_COLLECT_SECONDS, self._collect_when_idle)
        if self._open.get(document.uri) is not document:
            return
        document.snapshot = snapshot
        if document.revision == snapshot.revision:
            self._resolve(document, snapshot)
            self.on_analysed(snapshot)

    def _resolve(self, document: Document, snapshot: Snapshot | None) -> None:
        waiting, document._waiters = document._waiters, []
        for revision, future in waiting:
            if not future.done():
                future.set_result(
                    snapshot if snapshot is not None and snapshot.revision == revision else None
                )

    def _collect_when_idle(self) -> None:
        """:meth:`collect`, unless a document is being analysed (another document's analysis
        runs on: a collection then would walk the model it is building, holding every thread
        up for seconds on a large one); then later."""
        busy = any(d._timer is not None or (d._task is not None and not d._task.done()) for d in self)
        if busy:
            self._idle = asyncio.get_running_loop().call_later(IDLE_COLLECT_SECONDS, self._collect_when_idle)
        else:
            self._idle = None
            self.collect()

    @staticmethod
    def collect() -> None:
        """A full collection, of frozen objects too, then freeze what is left: cycles made
        during analyses (rare: exceptions, lark's error recovery) are freed here."""
        gc.unfreeze()
        gc.collect()
        gc.freeze()

    def shutdown(self) -> None:
        if self._idle is not None:
            self._idle.cancel()
        self._executor.shutdown(wait=False, cancel_futures=True)


def refused(uri: str, version: int | None, revision: int, why: str) -> Snapshot:
    """The snapshot of a text too large to analyse: one diagnostic saying so, and nothing else."""
    empty = SourceText("")
    return Snapshot(
        uri=uri,
        version=version,
        revision=revision,
        result=check(parse(empty)),
        positions=PositionIndex(empty),
        wire_diagnostics=[
            {
                "range": {"start": {"line": 0, "character": 0}, "end": {"line": 0, "character": 0}},
                "message": why,
                "severity": types.DiagnosticSeverity.Error.value,
                "source": SOURCE,
            }
        ],
        refused=True,
    )


# ---- grammars on disk, for workspace symbols ------------------------------------------------

_on_disk = WorkspaceGrammars()


def workspace_grammars(roots: Iterable[str], skip: set[str]) -> list[Snapshot]:
    """Snapshots of the grammar files under ``roots`` whose URIs are not in ``skip`` (the open ones)."""
    found = []
    for path in grammar_files(roots):
        uri = path.as_uri()
        if uri not in skip and (result := _on_disk.get(path)) is not None:
            found.append(Snapshot(uri, None, 0, result, PositionIndex(result.grammar.source), []))
    return found
