"""The language server under test: a real server process (``python -m gaitgram_lsp``)
driven over stdio by pytest-lsp's client, with the capabilities of real editors.

Expected diagnostics are computed here from ``check(parse(text))`` with positions worked
out independently of the server's own conversion code.
"""

from __future__ import annotations

import asyncio
import itertools
import sys
import time

import pytest_lsp
from lsprotocol import types
from pygls.protocol import default_converter
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities
from pytest_lsp.client import DEFAULT_CLIENT_FEATURES, register_lsp_features

from gaitgram.analysis import check
from gaitgram.language import parse
from gaitgram.language.diagnostics import Severity
from gaitgram.language.source import SourceText

SERVER = [sys.executable, "-m", "gaitgram_lsp"]
_uris = itertools.count(1)

#: A grammar with a bit of everything; line numbers are used by the tests.
WALK = """\
@start <gait>
@backend mujoco-horse
<gait> ::= <hip>;<neck>
@joint hip_hind limits=-20..30 free=11..
<hip> ::= <amp>*sin(2*PI*t)
<amp> ::= int[0..20]
<unused> ::= <amp> | <missing>
"""


class Client(LanguageClient):
    """pytest-lsp's client, recording every publishDiagnostics with its version."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.published: list[types.PublishDiagnosticsParams] = []


def _record(client: Client, params: types.PublishDiagnosticsParams) -> None:
    client.diagnostics[params.uri] = params.diagnostics
    client.published.append(params)


def make_client() -> Client:
    client = Client(converter_factory=default_converter)
    register_lsp_features(
        client, {**DEFAULT_CLIENT_FEATURES, types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS: _record}
    )
    return client


CONFIG = ClientServerConfig(server_command=SERVER, client_factory=make_client)


def capabilities(editor: str = "visual-studio-code") -> types.ClientCapabilities:
    return client_capabilities(editor)


@pytest_lsp.fixture(scope="module", config=CONFIG)
async def client(lsp_client: Client, tmp_path_factory):
    """A VS Code-like client (push diagnostics, UTF-16, snippets, markdown), one server per module.

    Its workspace folder holds one grammar file on disk, for workspace symbols."""
    folder = tmp_path_factory.mktemp("workspace")
    (folder / "on_disk.gg").write_text("<disk_rule> ::= a | <disk_other>\n<disk_other> ::= b\n")
    result = await lsp_client.initialize_session(
        types.InitializeParams(
            capabilities=capabilities(),
            workspace_folders=[types.WorkspaceFolder(uri=folder.as_uri(), name="workspace")],
        )
    )
    lsp_client.workspace_folder = folder  # type: ignore[attr-defined]
    lsp_client.server_capabilities = result.capabilities  # type: ignore[attr-defined]
    yield
    await lsp_client.shutdown_session()


def new_uri(name: str = "doc") -> str:
    """A fresh URI per test: tests share one server per module."""
    return f"file:///tmp/gaitgram-tests/{name}-{next(_uris)}.gg"


def open_document(client: Client, uri: str, text: str, version: int = 1) -> None:
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(
            text_document=types.TextDocumentItem(uri=uri, language_id="gaitgram", version=version, text=text)
        )
    )


def replace_all(client: Client, uri: str, version: int, text: str) -> None:
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
            content_changes=[types.TextDocumentContentChangeWholeDocument(text=text)],
        )
    )


def edit(client: Client, uri: str, version: int, range_: types.Range, text: str) -> None:
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
            content_changes=[types.TextDocumentContentChangePartial(range=range_, text=text)],
        )
    )


async def published(client: Client, uri: str, version: int, timeout: float = 20.0) -> list[types.Diagnostic]:
    """The diagnostics published for ``version`` of ``uri`` (waiting for them)."""
    deadline = time.monotonic() + timeout
    while True:
        for params in client.published:
            if params.uri == uri and params.version == version:
                return list(params.diagnostics)
        if time.monotonic() > deadline:
            seen = [p.version for p in client.published if p.uri == uri]
            raise TimeoutError(f"no diagnostics for version {version} of {uri}; published: {seen}")
        await asyncio.sleep(0.005)


def doc(uri: str) -> types.TextDocumentIdentifier:
    return types.TextDocumentIdentifier(uri=uri)


def at(line: int, character: int) -> types.Position:
    return types.Position(line=line, character=character)


def span(start: types.Position, end: types.Position) -> types.Range:
    return types.Range(start=start, end=end)


# ---- expectations, computed without the server's code ---------------------------------------

_SEVERITY = {
    Severity.ERROR: types.DiagnosticSeverity.Error,
    Severity.WARNING: types.DiagnosticSeverity.Warning,
    Severity.INFO: types.DiagnosticSeverity.Information,
}


def code_units(text: str, encoding: str) -> int:
    if encoding == "utf-8":
        return len(text.encode("utf-8", "surrogatepass"))
    if encoding == "utf-32":
        return len(text)
    return len(text.encode("utf-16-le", "surrogatepass")) // 2


def lsp_position(source: SourceText, offset: int, encoding: str = "utf-16") -> types.Position:
    location = source.location(offset)
    prefix = source.line_text(location.line)[: location.column - 1]
    return types.Position(line=location.line - 1, character=code_units(prefix, encoding))


def expected(
    text: str, encoding: str = "utf-16"
) -> list[tuple[str, str, types.Range, types.DiagnosticSeverity]]:
    """``gaitgram check``'s diagnostics of ``text``: code, message, range, severity."""
    result = check(parse(text))
    source = result.grammar.source
    return [
        (
            d.code.code,
            d.message,
            types.Range(
                start=lsp_position(source, d.span.start, encoding),
                end=lsp_position(source, d.span.end, encoding),
            ),
            _SEVERITY[d.level],
        )
        for d in result.diagnostics
    ]


def seen(diagnostics: list[types.Diagnostic]) -> list[tuple[str, str, types.Range, types.DiagnosticSeverity]]:
    return [(str(d.code), d.message, d.range, d.severity) for d in diagnostics]  # type: ignore[misc]


# ---- sharing the name "conftest" ---------------------------------------------------------------
# pytest imports every conftest.py outside a package as the module "conftest", the last one
# loaded winning; test modules elsewhere do `from conftest import GRAMMARS` and mean
# tests/conftest.py. Names this file does not define are taken from that one.
_root_conftest = None


def __getattr__(name: str):
    global _root_conftest
    if name.startswith("__"):
        raise AttributeError(name)
    if _root_conftest is None:
        import importlib.util
        from pathlib import Path

        path = Path(__file__).resolve().parents[1] / "conftest.py"
        spec = importlib.util.spec_from_file_location("_gaitgram_tests_conftest", path)
        assert spec is not None
        assert spec.loader is not None
        _root_conftest = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(_root_conftest)
    try:
        return getattr(_root_conftest, name)
    except AttributeError:
        raise AttributeError(f"module 'conftest' has no attribute {name!r}") from None
