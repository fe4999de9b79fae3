"""Run benchmarks: ``python -m benchmarks`` (all) or ``python -m benchmarks check``."""

from __future__ import annotations

import importlib
import pkgutil
import sys
from pathlib import Path


def main(argv: list[str]) -> int:
    here = Path(__file__).parent
    available = sorted(
        m.name.removeprefix("bench_")
        for m in pkgutil.iter_modules([str(here)])
        if m.name.startswith("bench_")
    )
    # Options after the names go to the one benchmark named (``ponyge2 --runs 5``).
    split = next((i for i, a in enumerate(argv) if a.startswith("-")), len(argv))
    names, options = argv[:split], argv[split:]
    if options and len(names) != 1:
        print("options (after the benchmark's name) need exactly one benchmark named first", file=sys.stderr)
        return 2
    chosen = names or available
    unknown = [name for name in chosen if name not in available]
    if unknown:
        print(
            f"unknown benchmark(s): {', '.join(unknown)}; available: {', '.join(available)}", file=sys.stderr
        )
        return 2
    for name in chosen:
        print(f"== {name} ==")
        module = importlib.import_module(f"benchmarks.bench_{name}")
        module.main(options) if options else module.main()
        print()
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
