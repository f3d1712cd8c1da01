"""Reading an SRDF's ``disable_collisions`` pairs, renamed into a model's namespace."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

from ..diagnostics import Span, did_you_mean
from ..sources import URDF, UnreadableSource, read_source
from .description import prefixed


def disabled_pairs(path: Path, prefix: str, links: list, diagnostics: list) -> set:
    """The ``disable_collisions`` pairs of the SRDF at ``path`` as frozensets of body
    names in namespace ``prefix``; ``links`` are the model's (renamed) links.

    Problems (malformed XML, a link the model does not have) go to ``diagnostics``.
    """
    try:
        source = read_source(path, URDF)
    except UnreadableSource as error:
        diagnostics.extend(error.diagnostics)
        return set()
    try:
        robot = ET.fromstring(source.text)
    except ET.ParseError as error:
        line, column = error.position
        diagnostics.append(source.error("urdf-error", f"malformed SRDF: {error.msg}",
                                        Span.point(line, column + 1)))
        return set()
    lines = [source.line(number) for number in range(1, source.line_count + 1)]
    pairs = set()
    for element in robot.iter("disable_collisions"):
        names = [prefixed(prefix, element.get(key, "")) for key in ("link1", "link2")]
        unknown = [name for name in names if name not in links]
        if unknown:
            written = element.get("link1" if unknown[0] == names[0] else "link2", "")
            line = next((number for number, text in enumerate(lines, 1)
                         if "disable_collisions" in text and f'"{written}"' in text), 1)
            diagnostics.append(source.error(
                "unknown-body", f"SRDF names link '{written}', which the model does not have",
                Span.point(line), did_you_mean(unknown[0], links)))
            continue
        pairs.add(frozenset(names))
    return pairs
