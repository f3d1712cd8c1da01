"""``robocop-mission check FILE...``: parse and check missions against their worlds.

Exit codes: 0 no error (warnings allowed unless ``--strict``), 1 errors, 2 usage error
(bad option, missing file).
"""

from __future__ import annotations

import contextlib
import dataclasses
import gc
import json
import sys

from ..diagnostics import ERROR, Diagnostic
from ..sources import not_a_file

FORMATS = ("text", "json", "github")


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "check", help="parse and check missions against their worlds",
        description="Parse each mission, load the world it names and check it. Prints "
                    "'FILE: OK' or every diagnostic as FILE:LINE:COL: error[CODE]: message.")
    parser.add_argument("files", nargs="+", metavar="FILE", help=".mission files")
    parser.add_argument("--format", choices=FORMATS, default="text",
                        help="text (default), json, or github workflow commands")
    parser.add_argument("--strict", action="store_true", help="treat warnings as errors")
    parser.add_argument("--world", metavar="WORLD.yaml",
                        help="check against this world instead of the one each mission names")
    parser.set_defaults(command=run)


def _strict(diagnostics, strict: bool) -> list[Diagnostic]:
    if not strict:
        return list(diagnostics)
    return [dataclasses.replace(d, severity=ERROR) for d in diagnostics]


def _count(number: int, word: str) -> str:
    return f"{number} {word}{'' if number == 1 else 's'}"


def _summary(path: str, diagnostics: list[Diagnostic]) -> str:
    errors = sum(d.is_error for d in diagnostics)
    warnings = len(diagnostics) - errors
    if not diagnostics:
        return f"{path}: OK"
    parts = [_count(errors, "error")] if errors else []
    parts += [_count(warnings, "warning")] if warnings else []
    return f"{path}: {', '.join(parts)}"


@contextlib.contextmanager
def _collector_paused():
    """Check without cyclic garbage collection. Importing the libraries and loading a
    world create some 60,000 objects that live as long as the process: each collection
    walked them again and found next to nothing. A checked file leaves a few hundred
    objects of cyclic garbage (about 250 kB), collected once the checks are done."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def _world(path: str | None):
    """The world of ``--world``, ``None`` without it, or its diagnostics."""
    if path is None:
        return None
    from ..diagnostics import DiagnosticError
    from ..world import load_world

    try:
        return load_world(path)
    except DiagnosticError as error:
        return list(error.diagnostics)


def run(args) -> int:
    """Check every file; exit 1 when any has an error."""
    from ..compile import WorldCache, check_file

    missing = [(name, not_a_file(name)) for name in args.files if not_a_file(name)]
    if missing:
        for name, problem in missing:
            print(f"robocop-mission check: error: {problem}: {name}", file=sys.stderr)
        return 2
    cache = WorldCache()
    reports = []
    with _collector_paused():
        world = _world(args.world)
        if isinstance(world, list):
            reports.append((args.world, world))
            world = None
        for name in args.files if not reports else ():
            result = check_file(name, world=world, cache=cache, compiled=False)
            reports.append((name, _strict(result.diagnostics, args.strict)))
    if args.format == "json":
        print(json.dumps([{"file": name, "ok": not any(d.is_error for d in found),
                           "diagnostics": [d.to_json() for d in found]}
                          for name, found in reports], indent=2))
    elif args.format == "github":
        for _, found in reports:
            for diagnostic in found:
                print(diagnostic.to_github())
    else:
        for name, found in reports:
            for diagnostic in found:
                print(diagnostic.render())
                print()
            print(_summary(name, found))
    return 1 if any(d.is_error for _, found in reports for d in found) else 0
