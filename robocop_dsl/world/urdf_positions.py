"""Where a URDF's elements and their attributes are written, for diagnostics that point
at them."""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from xml.parsers import expat

from ..diagnostics import SourceFile, Span


class ElementPositions:
    """The start tag of every element of a parsed URDF, located in its text.

    Args:
        source: The URDF file.
        root: The tree parsed from ``source.text``, before any change to it.
    """

    def __init__(self, source: SourceFile, root: ET.Element):
        self.source = source
        starts: list = []
        parser = expat.ParserCreate()

        def start(tag, attrs):
            line = parser.CurrentLineNumber
            encoded = self.source.line(line).encode()[:parser.CurrentColumnNumber]
            starts.append(self.source.offset(line, len(encoded.decode(errors="ignore")) + 1))

        parser.StartElementHandler = start
        try:
            parser.Parse(source.text, True)
        except expat.ExpatError:
            starts.clear()
        self._offsets = dict(zip(root.iter(), starts))

    def span(self, element: ET.Element, attribute: str | None = None) -> Span:
        """The span of ``attribute="..."`` in the start tag of ``element`` when it is
        written there, else of ``<TAG``; the file's first line for an element not
        found."""
        offset = self._offsets.get(element)
        if offset is None:
            return Span.point(1)
        text = self.source.text
        end = text.find(">", offset)
        tag = text[offset:end if end >= 0 else len(text)]
        found = re.search(rf"\s({re.escape(attribute)}\s*=\s*(\"[^\"]*\"|'[^']*'))", tag) \
            if attribute else None
        start, width = (offset + found.start(1), len(found.group(1))) if found \
            else (offset, len(element.tag) + 1)
        line, column = self.source.position(start)
        width = min(width, len(self.source.line(line)) - column + 1)
        return Span.point(line, column, width)
