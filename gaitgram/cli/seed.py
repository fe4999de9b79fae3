"""``gaitgram seed``: the paper's Fourier analysis of seed data, and grammars written from it."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console

from gaitgram import jsonio
from gaitgram.cli.common import check_output, err, fail, read_inputs, write_or_exit
from gaitgram.cli.options import within
from gaitgram.fileio import Input
from gaitgram.language.source import describe_os_error
from gaitgram.seed import SeedError, load_seed, read_seed_csv
from gaitgram.seed.dlc import FPS_RANGE
from gaitgram.seed.grammars import TARGET_FREQUENCY, Style, fit_seed, write_grammar

#: A Fourier term's amplitude, in degrees: a full turn is the most that means anything.
THRESHOLD = within("--threshold", 0, 360, " degrees")
#: The files ``seed derive`` reads in a folder of tracks.
TRACKS = (".h5", ".hdf5", ".csv")

app = typer.Typer(
    rich_markup_mode=None,  # help text is plain: brackets, as in pip extras, are kept
    help="Seed data: Fourier analysis and grammars in the paper's styles.",
    no_args_is_help=True,
)


def _seed(path: Path | None):
    try:
        return read_seed_csv(path) if path is not None else load_seed()
    except SeedError as error:
        raise fail(str(error)) from None


@app.command("fit")
def fit(
    csv: Annotated[Path | None, typer.Argument(help="Seed CSV [the bundled walk].")] = None,
    threshold: Annotated[
        float, typer.Option(callback=THRESHOLD, help="Drop terms with a smaller amplitude (degrees).")
    ] = 1.0,
    as_json: Annotated[bool, typer.Option("--json", help="One JSON object per joint.")] = False,
) -> None:
    """Decompose each joint's curve into a sum of sines and print it as grammar rules, with the
    reconstruction error of the written text."""
    seed = _seed(csv)
    try:
        fits = fit_seed(seed, threshold)
    except ValueError as error:
        raise fail(str(error)) from None
    out = Console(highlight=False, soft_wrap=True, markup=False)
    for joint, result in fits.items():
        if as_json:
            out.out(
                jsonio.dumps(
                    {
                        "joint": joint,
                        "text": result.text,
                        "terms": len(result.terms),
                        "dropped": len(result.dropped),
                        "rms_error": result.rms_error,
                        "max_error": result.max_error,
                    }
                )
            )
        else:
            out.out(
                f"<seed_{joint}> ::= {result.text}  "
                f"# rms {result.rms_error:.3f}, max {result.max_error:.3f}, "
                f"{len(result.terms)} terms kept, {len(result.dropped)} dropped"
            )


@app.command("grammar")
def grammar(
    style: Annotated[Style, typer.Option(help="One of the paper's grammar styles.")],
    output: Annotated[
        Path | None, typer.Option("--output", "-o", help="Write here [standard output].")
    ] = None,
    seed_csv: Annotated[Path | None, typer.Option("--seed", help="Seed CSV [the bundled walk].")] = None,
    threshold: Annotated[
        float,
        typer.Option(callback=THRESHOLD, help="Fourier terms under this amplitude (degrees) are dropped."),
    ] = 1.0,
    force: Annotated[bool, typer.Option("--force", help="Overwrite OUTPUT.")] = False,
    imposed_frequency: Annotated[
        bool,
        typer.Option(
            "--imposed-frequency",
            help="Leave out the @frequency rule: the backend imposes the stride frequency, as in the paper.",
        ),
    ] = False,
) -> None:
    """Write a grammar from the seed in one of the paper's styles."""
    if output is not None:
        check_output(output, force=force, flag="-o", inputs=read_inputs((seed_csv, "the --seed CSV")))
    seed = _seed(seed_csv)
    command = (
        f"gaitgram seed grammar --style {style.value}"
        + (" --imposed-frequency" if imposed_frequency else "")
        + (f" -o {output}" if output else "")
    )
    frequency = None if imposed_frequency else TARGET_FREQUENCY
    try:
        text = write_grammar(style, seed, threshold=threshold, command=command, frequency=frequency)
    except ValueError as error:  # a seed whose curves leave the style no room within the limits
        raise fail(str(error)) from None
    if output is None:
        typer.echo(text, nl=False)
        return
    write_or_exit(output, text)
    err.print(f"wrote {output}")


@app.command("derive")
def derive(
    tracks: Annotated[
        list[Path], typer.Argument(help="DeepLabCut tracks (.h5, .csv) of walking horses, or their folders.")
    ],
    output: Annotated[Path, typer.Option("--output", "-o", help="Write the summary (JSON) here.")],
    fps: Annotated[
        float,
        typer.Option(
            callback=within("--fps", *FPS_RANGE), help="Frames per second of the videos, 1 to 1000."
        ),
    ] = 15.0,
    force: Annotated[bool, typer.Option("--force", help="Overwrite an existing output.")] = False,
) -> None:
    """Measure real walks: footfall timing (stride frequency, duty factor, the phase at which each
    hoof lands) and stride-normalised angle curves (fetlocks, limb protraction, head-neck), as
    DeepLabCut side-view tracks allow; h5 files need pip install 'gaitgram[dlc]'."""
    from gaitgram.extras import MissingExtra
    from gaitgram.seed.dlc import DlcError, measure, read_clip, summarise

    check_output(output, force=force, flag="-o", inputs=[_track_input(path) for path in tracks])
    try:
        files = sorted(
            f
            for path in tracks
            for f in (path.iterdir() if path.is_dir() else [path])
            if not path.is_dir() or f.suffix.lower() in TRACKS
        )
    except OSError as error:
        raise fail(f"cannot read {error.filename}: {describe_os_error(error)}") from None
    if not files:
        raise fail(f"no .h5 or .csv tracks in {', '.join(map(str, tracks))}")
    try:
        summary = summarise(measure(read_clip(f, fps) for f in files))
    except (DlcError, MissingExtra) as error:
        raise fail(str(error)) from None
    write_or_exit(output, jsonio.dumps(summary, indent=1) + "\n")
    duty, offsets = summary["duty_factor"], summary["phase_after_left_hind"]
    lands = ", ".join(f"{h} {o['median']:.2f}" for h, o in offsets.items())  # type: ignore[union-attr]
    err.print(
        f"{summary['clips']} clips, {summary['strides']} strides: {summary['stride_frequency_hz']:.2f} Hz, "
        f"duty factor {duty['median']:.2f}; hooves land at {lands}; wrote {output}"  # type: ignore[index]
    )


def _track_input(path: Path) -> Input:
    """A track, or a folder of them whose tracks (and whatever would be read as one next time: a
    file of a track's suffix at its top) no output may be."""
    if not path.is_dir():
        return Input(path, "the track")
    return Input(
        path,
        "the folder of tracks",
        lambda parts: len(parts) == 1 and Path(parts[0]).suffix.lower() in TRACKS,
    )
