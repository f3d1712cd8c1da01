"""Syntax errors: label them with what was expected and recover to report the next ones.

:class:`Recovery` is the ``on_error`` handler of lark's LALR parser. On an unexpected
token it first tries the typical mistakes (a missing ``->``, ``}``, ``)``, ``]``, ``=``
or ``:``; ``:`` written for ``=`` and back) by feeding the interactive parser the token
that was meant; otherwise it reports the token with the expected ones, skips the rest
of the statement and pops the parser back to where the statement began.

A block left open is reported at its ``{``. Where it should have ended, the parser
cannot tell (a state's block may hold states); the indentation can:
:func:`layout_closings` finds the blocks that a later line, indented no deeper than the
line of their ``{``, shows to be over, and where to close each.
"""

from __future__ import annotations

import dataclasses

import difflib
import functools
import re
from dataclasses import dataclass

from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedCharacters, UnexpectedInput, UnexpectedToken

from ..diagnostics import Diagnostic, SourceFile, Span

# Words that start a statement (and ``parallel``) are reserved everywhere, so that a
# misplaced one reads as itself ("unexpected 'when'") rather than as a name. The others
# (``world`` and ``controller`` among them) stay usable as names.
RESERVED = frozenset({
    "mission", "library", "import", "let", "behavior", "constraint", "task", "start",
    "state", "final", "parallel", "region", "when", "enter", "during", "exit", "enable",
    "disable", "reset", "attach", "detach", "emit", "log"})

_SUBSTITUTES = {"COLON": "EQUAL", "EQUAL": "COLON"}
_INSERTIONS = (("_ARROW",), ("RBRACE",), ("RPAR",), ("RSQB",), ("EQUAL",), ("COLON",),
               ("RBRACE", "_NL"), ("RSQB", "_NL"), ("RPAR", "_NL"), ("_NL",))
_MID_LINE_INSERTIONS = (_INSERTIONS[0], ("_NL",), *_INSERTIONS[1:-1])
"""Before a token that is not the first of its line, a missing new line comes before a
missing '}' (a second statement written on the line, not the block's end)."""
_SYNC = ("_NL", "RBRACE")
# Parsed statements that recovery never discards while looking for a place to resume.
_COMPLETE = frozenset({
    "mission_header", "library_header", "import_decl", "let_decl", "world_decl",
    "controller_decl", "constraint_decl", "task_decl", "event_decl", "behavior_decl",
    "behavior_param", "machine_body", "start_decl", "state_decl", "instance_state",
    "parallel_state", "final_decl", "transition", "region", "param", "param_block",
    "state_body", "parallel_body", "part_body", "action_block", "actions", "enable",
    "disable", "reset", "assign", "attach", "detach", "emit", "log"})
_NAMED = {"NAME": "a name", "NUMBER": "a number", "STRING": "a string", "UNIT": "a unit",
          "_NL": "a new line", "$END": "the end of the file", "COMPARE": "a comparison",
          "_ARROW": "'->'"}
_BODIES = {"state": ("state _ {", "}"), "final": ("state _ {", "}"),
           "parallel": ("state _: parallel {", "}"), "region": ("behavior _() {", "}"),
           "behavior": ("behavior _() {", "}"), "task": ("task _: t() {", "}"),
           "constraint": ("constraint _: t() {", "}"),
           **{kind: (f"state _ {{ {kind} {{", "} }") for kind in ("enter", "during", "exit")}}
"""Per keyword of a statement with a block, a header of its kind and what closes the
block and the header (the contents of a block whose header did not parse are parsed
after it)."""
_PARALLEL = re.compile(r"^\s*state\b.*:\s*parallel\b")
_GENERIC_HINT_LIMIT = 8
CONTINUED = re.compile(r"(?:[,(\[]|\band|\bor|\bnot)\s*$")
"""The end of a line whose statement goes on on the next line."""
LINE_STARTS = RESERVED - {"parallel"}
"""The keywords that begin a statement or an action: a line that starts with one (or
with ``}``) never goes on with the line before it, whatever that line ends with."""
_NEW_STATEMENT = re.compile(rf"\s*(?:(?:{'|'.join(sorted(LINE_STARTS))})\b|}})")
UNCLOSED = "missing '}' for this '{'"


def _interchangeable(kind: str) -> tuple[str, ...]:
    """Names and units are lexed alike outside their context; try both."""
    return ("NAME", "UNIT") if kind in ("NAME", "UNIT") else (kind,)


class Recovery:
    """The parser's ``on_error`` handler; collects diagnostics in ``diagnostics``."""

    def __init__(self, source: SourceFile, parser: Lark):
        self.source = source
        self.diagnostics: list[Diagnostic] = []
        self.unclosed: list[Token] = []
        """The ``{`` tokens that recovery closed."""
        self._skip_line: int | None = None
        self._literals = {t.name: t.pattern.value for t in parser.terminals
                          if t.pattern.type == "str"}

    # ---- the handler ----
    def __call__(self, error: UnexpectedInput) -> bool:
        if isinstance(error, UnexpectedCharacters):
            self._bad_character(error)
            return True
        if not isinstance(error, UnexpectedToken) or error.interactive_parser is None:
            return False
        parser, token = error.interactive_parser, error.token
        if token.type == "$END":
            self._finish(parser, token)
            return True
        skipping = self._skip_line is not None and token.line == self._skip_line
        if not skipping:
            self._skip_line = None
            if self._repair(parser, token):
                return True
            self._unexpected(parser, token)
            self._skip_line = token.line
        if token.type == "LBRACE":
            self._skip_block(parser, token)
        elif token.type in _SYNC:
            self._resync(parser, token)
        return True

    def give_up(self, error: Exception) -> None:
        """Parsing stopped for good: make sure the file is not reported clean."""
        if not any(d.is_error for d in self.diagnostics):
            line = getattr(error, "line", 1) or 1
            column = getattr(error, "column", 1) or 1
            self._add("syntax-error", "cannot parse the mission past this point",
                      Span.point(line, column), None)

    # ---- typical mistakes ----
    def _repair(self, parser, token: Token) -> bool:
        substitute = _SUBSTITUTES.get(token.type)
        if substitute and _accepts(parser, substitute, token):
            parser.feed_token(Token.new_borrow_pos(substitute, token.value, token))
            wanted, found = self._show(substitute), self._show(token.type)
            hint = ("a parameter or field is set with 'NAME = VALUE'" if substitute == "EQUAL"
                    else "a declaration names its type after ':' (task NAME: TYPE(...))")
            self._add("wrong-token", f"expected {wanted} here, not {found}", _span(token), hint)
            return True
        text = parser.lexer_thread.state.text.text
        first_on_line = not text[text.rfind("\n", 0, token.start_pos) + 1:token.start_pos].strip()
        for inserted in _INSERTIONS if first_on_line else _MID_LINE_INSERTIONS:
            trial = _trial(parser)
            if not _feed_all(trial, inserted, token):
                continue
            kind = next((k for k in _interchangeable(token.type) if _accepts(trial, k, token)),
                        None)
            if kind is None:
                continue
            opened = _open_brace(parser) if inserted[0] == "RBRACE" else None
            _feed_all(parser, inserted, token)
            parser.feed_token(Token.new_borrow_pos(kind, token.value, token))
            if opened is not None:
                self.close(opened, f"close it before line {token.line}")
            else:
                self._missing(inserted[0], token)
            return True
        meant = self._keyword_meant(parser, token)
        if meant is not None:
            parser.feed_token(Token.new_borrow_pos(meant, token.value, token))
            self._add("syntax-error", f"unexpected {self._describe(token)}", _span(token),
                      f"did you mean '{self._literals[meant]}'?")
            return True
        if token.value in RESERVED and _accepts(parser, "NAME", token):
            parser.feed_token(Token.new_borrow_pos("NAME", token.value, token))
            self._add("reserved-word", f"'{token.value}' is a reserved word, not a name",
                      _span(token), "choose another name")
            return True
        return False

    def _keyword_meant(self, parser, token: Token) -> str | None:
        """The keyword that a name where none may come misspells (read as that
        keyword, so that what follows parses), or ``None``."""
        if token.type not in ("NAME", "UNIT"):
            return None
        keywords = {self._literals[k]: k for k in parser.accepts()
                    if self._literals.get(k, "").isidentifier()}
        meant = difflib.get_close_matches(token.value, keywords, n=1, cutoff=0.75)
        return keywords[meant[0]] if meant else None

    def close(self, brace: Token, hint: str) -> None:
        """Report a ``{`` that is never closed, at that ``{``."""
        self.unclosed.append(brace)
        self._add("missing-token", UNCLOSED, _span(brace), hint)

    def _missing(self, kind: str, token: Token) -> None:
        if kind == "_NL":
            self._add("missing-token", f"expected a new line before {self._describe(token)}",
                      _span(token), "write one statement per line")
            return
        what = self._show(kind)
        message = f"missing {what} before {self._describe(token)}"
        hints = {"_ARROW": "a transition is written 'when CONDITION -> STATE'",
                 "EQUAL": "a parameter or field is set with 'NAME = VALUE'",
                 "COLON": "a declaration names its type after ':' (task NAME: TYPE(...))"}
        self._add("missing-token", message, _span(token), hints.get(kind))

    # ---- generic errors ----
    def _unexpected(self, parser, token: Token) -> None:
        expected = sorted(self._show(k) for k in parser.accepts())
        if token.type == "EQUAL" and "a comparison" in expected:
            self._add("syntax-error", "'=' is not a comparison", _span(token),
                      "compare with <, <=, > or >=")
            return
        shown = expected[:_GENERIC_HINT_LIMIT] + (["..."] if len(expected) > _GENERIC_HINT_LIMIT
                                                  else [])
        hint = "expected " + ", ".join(shown) if expected else None
        self._add("syntax-error", f"unexpected {self._describe(token)}", _span(token), hint)

    def _bad_character(self, error: UnexpectedCharacters) -> None:
        if self._skip_line == error.line:
            return
        char = self.source.text[error.pos_in_stream:error.pos_in_stream + 1]
        span = Span.point(error.line, error.column)
        if char == '"':
            self._add("unterminated-string", "unterminated string", span,
                      "close the string with '\"' on the same line")
        else:
            self._add("bad-character", f"unexpected character {char!r}", span,
                      "names are letters, digits and '_'; comments start with '#'")
        self._skip_line = error.line

    def _finish(self, parser, token: Token) -> None:
        """At the end of the file: close open blocks (reporting each) and stop."""
        reported = False
        for _ in range(10_000):
            if _accepts(parser, "$END", token):
                return
            if _accepts(parser, "RBRACE", token):
                opened = _open_brace(parser)
                if opened is not None:
                    self.close(opened, "close it at the end of the file")
                parser.feed_token(Token.new_borrow_pos("RBRACE", "}", token))
            elif _accepts(parser, "_NL", token):
                parser.feed_token(Token.new_borrow_pos("_NL", "", token))
            else:
                if not reported:
                    self._add("syntax-error", "unexpected end of the file",
                              _end_span(self.source),
                              "expected " + ", ".join(sorted(self._show(k)
                                                             for k in parser.accepts())))
                    reported = True
                _pop(parser, 1)

    def _skip_block(self, parser, token: Token) -> None:
        """The ``{`` that ends the header of a statement that did not parse: its block
        is skipped whole, to its matching ``}``, with the unfinished statement. Its
        contents would otherwise be read as statements of the block around it, each an
        error; their own syntax errors are reported (:meth:`_inside`). A ``{`` with
        code after it on its line opens a block only when its ``}`` is on that line
        (a one-line block); a block never closed is left to the closing of blocks at
        the end or by layout."""
        lexer = parser.lexer_thread.state
        text, at = lexer.text.text, lexer.line_ctr.char_pos
        end = _matching_brace(text, token.end_pos)
        if end is None or end < at or (_code_after(text, token.end_pos)
                                       and end > _line_end(text, token.end_pos)):
            return
        self._inside(text, token, end)
        lexer.line_ctr.feed(text[at:end])
        self._resync(parser, Token.new_borrow_pos("_NL", "", token))
        if not _code_after(text, end):
            self._skip_line = token.line + text.count("\n", token.end_pos, end)

    def _inside(self, text: str, brace: Token, end: int) -> None:
        """The syntax errors inside a block that :meth:`_skip_block` skips (from
        ``brace`` to index ``end`` of ``text``, just past its ``}``): its contents are
        parsed after a header of its kind (the nearest keyword to the header's first
        word), their lines the file's."""
        if end <= _line_end(text, brace.end_pos):     # a one-line block: nothing inside
            return
        header = code_of(text[text.rfind("\n", 0, brace.start_pos) + 1:brace.start_pos])
        words = header.split()
        kind = difflib.get_close_matches(words[0], _BODIES, n=1, cutoff=0.6) if words else []
        if not kind:
            return
        opening, closing = _BODIES["parallel" if _PARALLEL.search(header) else kind[0]]
        inner = text[_line_end(text, brace.end_pos) + 1:end - 1]
        from .parser import parse_mission

        last = brace.line + inner.count("\n") + 1      # the line of the block's '}'
        parsed = parse_mission(f"{opening}\n{inner}\n{closing}\n", self.source.path,
                               brace.line)
        self.diagnostics += [dataclasses.replace(d, source_line=self.source.line(d.span.line))
                             for d in parsed.diagnostics
                             if d.span is not None and brace.line < d.span.line <= last]

    def _resync(self, parser, token: Token) -> None:
        """Pop the unfinished statement so that ``token`` (a newline or '}') fits.

        Parsed statements are never popped; when the token fits nowhere above them it
        is dropped, and a newline still ends the unfinished statement.
        """
        unfinished = _unfinished(parser)
        for depth in range(unfinished + 1):
            trial = _trial(parser)
            _pop(trial, depth)
            if _accepts(trial, token.type, token):
                _pop(parser, depth)
                parser.feed_token(token)
                self._skip_line = None
                return
        if token.type == "_NL":
            _pop(parser, unfinished)
            self._skip_line = None

    # ---- wording ----
    def _show(self, kind: str) -> str:
        if kind in _NAMED:
            return _NAMED[kind]
        return repr(self._literals.get(kind, kind.lower()))

    def _describe(self, token: Token) -> str:
        if token.type == "_NL":
            return "end of line"
        if token.type in ("NAME", "UNIT"):
            return f"name '{token.value}'"
        if token.type == "NUMBER":
            return f"number {token.value}"
        if token.type == "STRING":
            return f"string {token.value}"
        return self._show(token.type)

    def _add(self, code: str, message: str, span: Span, hint: str | None) -> None:
        self.diagnostics.append(self.source.error(code, message, span, hint))


def _span(token: Token) -> Span:
    width = len(token.value) if token.type not in ("_NL", "$END") else 1
    return Span.point(token.line or 1, token.column or 1, width)


def _end_span(source: SourceFile) -> Span:
    """Just past the last non-blank line's code, lines counted as the lexer counts them."""
    number = next((n for n in range(source.line_count, 0, -1) if source.line(n).strip()), 1)
    return Span.point(number, len(source.line(number).rstrip()) + 1)


def _trial(parser):
    """A copy of ``parser`` to try tokens on.

    Reductions may append to the children of the trees on the value stack (lark reuses
    them for left recursion), so those trees are copied, one level deep: cheaper than the
    deep copy of ``parser.copy()`` and as safe for the stack's own values.
    """
    trial = parser.copy(deepcopy_values=False)
    state = trial.parser_state
    state.value_stack = [Tree(v.data, list(v.children), meta=v._meta)
                         if isinstance(v, Tree) else v for v in state.value_stack]
    return trial


def _accepts(parser, kind: str, near: Token) -> bool:
    trial = _trial(parser)
    try:
        trial.feed_token(Token.new_borrow_pos(kind, "", near))
    except UnexpectedInput:
        return False
    return True


def _feed_all(parser, kinds: tuple[str, ...], near: Token) -> bool:
    try:
        for kind in kinds:
            parser.feed_token(Token.new_borrow_pos(kind, "", near))
    except UnexpectedInput:
        return False
    return True


def _is_parsed_statement(value) -> bool:
    """A statement (or a run of them) that parsed: recovery keeps it."""
    data = getattr(value, "data", None)
    if data is None:
        return False
    return data in _COMPLETE or any(getattr(c, "data", None) in _COMPLETE
                                    for c in value.children)


def _unfinished(parser) -> int:
    """How many values of the parser's stack the statement it is in holds (above the
    last statement that parsed)."""
    stack = parser.parser_state.value_stack
    return next((depth for depth in range(len(stack))
                 if _is_parsed_statement(stack[-1 - depth])), len(stack))


def _line_end(text: str, at: int) -> int:
    """Where the line holding index ``at`` of ``text`` ends (its newline, or the end)."""
    end = text.find("\n", at)
    return len(text) if end < 0 else end


def _code_after(text: str, at: int) -> bool:
    """Whether code (not blanks, not a comment) follows index ``at`` on its line."""
    return bool(code_of(text[at:_line_end(text, at)]).strip())


def _matching_brace(text: str, start: int) -> int | None:
    """The index just past the ``}`` that closes a ``{`` ending at ``start`` in
    ``text`` (braces in strings and comments do not count: :func:`code_of`, line by
    line, as neither goes on over a line), or ``None``."""
    depth, at = 1, start
    while at <= len(text):
        end = _line_end(text, at)
        for column, char in enumerate(code_of(text[at:end])):
            if char in "{}":
                depth += 1 if char == "{" else -1
                if depth == 0:
                    return at + column + 1
        at = end + 1
    return None


def _pop(parser, depth: int) -> None:
    state = parser.parser_state
    for _ in range(min(depth, len(state.value_stack))):
        state.state_stack.pop()
        state.value_stack.pop()


def _open_brace(parser) -> Token | None:
    """The innermost '{' still open on the parser's stack."""
    for value in reversed(parser.parser_state.value_stack):
        if isinstance(value, Token) and value.type == "LBRACE":
            return value
    return None


@functools.cache
def _strings_and_comments() -> re.Pattern:
    from .parser import mission_grammar

    grammar = mission_grammar()
    string = grammar.get_terminal("STRING").pattern.to_regexp()
    comment = grammar.get_terminal("COMMENT").pattern.to_regexp()
    return re.compile(f"(?P<string>{string})|{comment}")


def _hide(match: re.Match) -> str:
    return ('"' if match.group("string") else " ") * len(match.group())


def comment_start(line: str) -> int | None:
    """Where the comment of ``line`` starts (a ``#`` in a string starts none)."""
    if "#" not in line:
        return None
    return next((m.start() for m in _strings_and_comments().finditer(line)
                 if not m.group("string")), None)


def code_of(line: str) -> str:
    """``line`` with the characters of its strings replaced by ``"`` and its comment by
    spaces: braces in them are text, and columns stay where they are."""
    return _strings_and_comments().sub(_hide, line) if '"' in line or "#" in line else line


@dataclass(frozen=True)
class Closing:
    """A block the layout shows to be over: its ``{`` (1-based line and column), its
    last line ``at`` (its ``}`` goes after it: see :func:`closing_places`) and the line
    it goes before (``None``: the end of the file)."""

    line: int
    column: int
    at: int
    before: int | None

    @property
    def hint(self) -> str:
        if self.before is None:
            return "close it at the end of the file"
        return f"close it before line {self.before}"


def layout_closings(text: str) -> list[Closing]:
    """The blocks whose ``{`` a later line shows to be over by its indentation, with
    no ``}`` before it: a line indented no deeper than the line that opened the block
    (a ``}`` less deep than it), or the end of the file. A line that continues the
    statement before it (after ``,``, ``(``, ``[``, ``and``, ``or``, ``not``) does not
    count, but for one that begins a statement (the line before it was left half
    typed)."""
    opened: list[tuple[int, int, int]] = []          # line, column, indentation
    found: list[Closing] = []
    last, continued = 0, False
    for number, line in enumerate(text.split("\n"), 1):
        code = code_of(line)
        if not code.strip():
            continue
        indent = len(line) - len(line.lstrip())
        if not continued or _NEW_STATEMENT.match(code):
            closing = code.lstrip().startswith("}")
            while opened and (indent < opened[-1][2] or (indent == opened[-1][2]
                                                         and not closing)):
                brace = opened.pop()
                found.append(Closing(brace[0], brace[1], last, number))
        for column, char in enumerate(code, 1):
            if char == "{":
                opened.append((number, column, indent))
            elif char == "}" and opened:
                opened.pop()
        last, continued = number, bool(CONTINUED.search(code))
    found += [Closing(line, column, last, None) for line, column, _ in reversed(opened)]
    return found


def closing_places(text: str, closings: list[Closing]) -> dict[int, list[Closing]]:
    """The lines where the ``}`` of ``closings`` go, and the closings on each: the first
    line without code after the block's last line, before the line that shows it over,
    when there is one (after an unfinished statement, the ``}`` would be read as its
    end); else after the code of the block's last line."""
    lines = text.split("\n")
    places: dict[int, list[Closing]] = {}
    for closing in closings:
        last = closing.before - 1 if closing.before else len(lines)
        line = next((n for n in range(closing.at + 1, last + 1)
                     if not code_of(lines[n - 1]).strip()), closing.at)
        places.setdefault(line, []).append(closing)
    return places


def closed_by_layout(text: str, places: dict[int, list[Closing]]) -> str:
    """``text`` with the ``}`` of each closing on its line (see :func:`closing_places`)."""
    lines = text.split("\n")
    for at, closings in places.items():
        line = lines[at - 1]
        end = len(code_of(line).rstrip())
        lines[at - 1] = line[:end] + "}" * len(closings) + line[end:]
    return "\n".join(lines)
