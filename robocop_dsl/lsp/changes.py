"""An open document's text after the editor's changes (``didChange``). A change's range
is found from the place of the previous one: typing moves little, so finding a line
costs the lines between, not the whole text; and a line's characters are counted in
code units only when it is not ASCII. A range whose end comes before its start is read
as the text between its two ends, as the editors' own ranges and the reference text
document of ``vscode-languageserver`` read it."""

from __future__ import annotations

from lsprotocol import types
from pygls.workspace.position_codec import UnitCounter


def _column(line: str, units: int, counter: UnitCounter) -> int:
    """The character column ``units`` code units into ``line`` (its end at most)."""
    if line.isascii():
        return min(units, len(line))
    counted = 0
    for index, char in enumerate(line):
        if counted >= units:
            return index
        counted += counter.code_units_for_char(char)
    return len(line)


def reversed_range(change) -> bool:
    """Whether a change's range ends before it starts."""
    if isinstance(change, types.TextDocumentContentChangeWholeDocument):
        return False
    start, end = change.range.start, change.range.end
    return (end.line, end.character) < (start.line, start.character)


class Texts:
    """Applies changes to texts, remembering for each text the start of the line the
    last change was on."""

    def __init__(self, counter: UnitCounter):
        self.counter = counter
        self._mark: tuple[str, int, int] | None = None   # text, line, offset of its start

    def _line_start(self, text: str, line: int) -> int:
        """The offset of the start of 0-based ``line`` (the end of the text past it)."""
        known_line, offset = 0, 0
        if self._mark is not None and self._mark[0] is text:
            known_line, offset = self._mark[1], self._mark[2]
        while known_line < line:
            found = text.find("\n", offset)
            if found < 0:
                return len(text)
            known_line, offset = known_line + 1, found + 1
        while known_line > line:
            offset = text.rfind("\n", 0, offset - 1) + 1
            known_line -= 1
        return offset

    def _offset(self, text: str, position: types.Position) -> int:
        start = self._line_start(text, position.line)
        end = text.find("\n", start)
        line = text[start:end if end >= 0 else len(text)]
        return start + _column(line, position.character, self.counter)

    def apply(self, text: str, change) -> str:
        """``text`` after one content change of ``didChange``."""
        if isinstance(change, types.TextDocumentContentChangeWholeDocument):
            self._mark = None
            return change.text
        first, last = change.range.start, change.range.end
        if reversed_range(change):
            first, last = last, first
        start = self._offset(text, first)
        line_start = self._line_start(text, first.line)
        end = self._offset(text, last) if last != first else start
        changed = text[:start] + change.text + text[end:]
        self._mark = (changed, first.line, line_start)
        return changed
