"""YAML reading that keeps where every key and item came from (1-based lines).

Untrusted YAML is bounded: nesting deeper than :data:`MAX_DEPTH` and aliases that
expand to more than :data:`MAX_NODES` nodes (an "alias bomb") or into themselves are
located ``yaml-syntax`` errors, found before any object is built.
"""

from __future__ import annotations

import yaml
from yaml.composer import ComposerError
from yaml.constructor import ConstructorError
from yaml.nodes import MappingNode, ScalarNode, SequenceNode

from ..diagnostics import DiagnosticError, SourceFile, Span


class YamlMap(dict):
    """A mapping that remembers the line and column of each key and of itself."""

    line = 1
    column = 1

    def __init__(self):
        super().__init__()
        self.key_spans: dict = {}
        self.value_spans: dict = {}

    def span(self, key=None) -> Span:
        """Span of ``key`` (or of the mapping when ``key`` is absent or unknown)."""
        if key in self.key_spans:
            return self.key_spans[key]
        return Span.point(self.line, self.column)

    def value_span(self, key) -> Span:
        """Span of the value written for ``key`` (falls back to the key's span)."""
        return self.value_spans.get(key) or self.span(key)


class YamlList(list):
    """A sequence that remembers the line and column of each item and of itself."""

    line = 1
    column = 1

    def __init__(self):
        super().__init__()
        self.item_spans: list[Span] = []

    def span(self, index=None) -> Span:
        if index is not None and 0 <= index < len(self.item_spans):
            return self.item_spans[index]
        return Span.point(self.line, self.column)


def _span(node) -> Span:
    start, end = node.start_mark, node.end_mark
    if end.line != start.line:
        return Span.point(start.line + 1, start.column + 1, 1)
    return Span(start.line + 1, start.column + 1, end.line + 1, end.column + 1)


MAX_DEPTH = 64
MAX_NODES = 100_000


class TooLarge(ComposerError):
    """A document past the bounds: too deep, too large once expanded, or recursive."""

    hint = "write the values out: a world or campaign file needs no deep nesting or aliases"


class DuplicateKey(ConstructorError):
    """A mapping that sets one key twice (YAML would keep the last silently)."""

    hint = "keep one of them"


class _Loader(yaml.SafeLoader):
    """PyYAML's safe loader with the nesting depth and the expanded size bounded."""

    def __init__(self, stream):
        super().__init__(stream)
        self._depth = 0

    def compose_node(self, parent, index):
        self._depth += 1
        try:
            if self._depth > MAX_DEPTH:
                raise TooLarge(None, None, f"nested more than {MAX_DEPTH} levels deep",
                                    self.peek_event().start_mark)
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1

    def construct_document(self, node):
        _check_expansion(node)
        return super().construct_document(node)


def _children(node) -> list:
    if isinstance(node, SequenceNode):
        return list(node.value)
    if isinstance(node, MappingNode):
        return [part for pair in node.value for part in pair]
    return []


def _check_expansion(root) -> None:
    """Raise a located ``ComposerError`` when ``root`` with every alias expanded has more
    than :data:`MAX_NODES` nodes or contains itself (counted without expanding)."""
    sizes: dict[int, int] = {}
    open_nodes: set[int] = set()
    stack = [(root, False)]
    while stack:
        node, finished = stack.pop()
        key = id(node)
        if finished:
            open_nodes.discard(key)
            sizes[key] = 1 + sum(sizes[id(child)] for child in _children(node))
            if sizes[key] > MAX_NODES:
                raise TooLarge(None, None, f"aliases expand to more than {MAX_NODES} "
                                    "values", node.start_mark)
        elif key in open_nodes:
            raise TooLarge(None, None, "an alias refers to a value that contains it",
                                node.start_mark)
        elif key not in sizes:
            open_nodes.add(key)
            stack.append((node, True))
            stack += [(child, False) for child in _children(node)]


def _expect(node, kind, what: str) -> None:
    if not isinstance(node, kind):
        raise ConstructorError(None, None, f"expected {what}", node.start_mark)


def _construct_map(loader: _Loader, node) -> YamlMap:
    _expect(node, MappingNode, "a mapping")
    _refuse_duplicates(node)
    loader.flatten_mapping(node)
    result = YamlMap()
    result.line, result.column = node.start_mark.line + 1, node.start_mark.column + 1
    for key_node, value_node in node.value:
        if not isinstance(key_node, ScalarNode):
            raise ConstructorError(None, None, "a key must be a single value, not a list "
                                   "or a mapping", key_node.start_mark)
        key = loader.construct_object(key_node, deep=True)
        result[key] = loader.construct_object(value_node, deep=True)
        result.key_spans[key] = _span(key_node)
        result.value_spans[key] = _span(value_node)
    return result


def _refuse_duplicates(node) -> None:
    """Raise :class:`DuplicateKey` at the second of two keys written alike in ``node``
    (a merge key's ``<<`` keys may be overridden: they are not among them)."""
    first: dict = {}
    for key_node, _ in node.value:
        if not isinstance(key_node, ScalarNode) or key_node.tag == "tag:yaml.org,2002:merge":
            continue
        line = first.setdefault(key_node.value, key_node.start_mark.line + 1)
        if line != key_node.start_mark.line + 1:
            raise DuplicateKey(None, None, f"the key {key_node.value!r} is set twice (first "
                               f"at line {line})", key_node.start_mark)


def _construct_list(loader: _Loader, node) -> YamlList:
    _expect(node, SequenceNode, "a list")
    result = YamlList()
    result.line, result.column = node.start_mark.line + 1, node.start_mark.column + 1
    for item in node.value:
        result.append(loader.construct_object(item, deep=True))
        result.item_spans.append(_span(item))
    return result


def _scalar(construct, what: str):
    """``construct`` of a YAML scalar, a value it cannot convert (an explicit ``!!float``
    or ``!!bool`` on a word, an integer of more than 4300 digits) a located error."""
    def build(loader: _Loader, node):
        try:
            return construct(loader, node)
        except (ValueError, KeyError):
            shown = node.value if len(node.value) <= 20 else node.value[:20] + "..."
            raise ConstructorError(None, None, f"cannot read {shown!r} as {what}",
                                   node.start_mark) from None
    return build


def _refuse(loader: _Loader, node):
    """A value of a type no world or campaign file holds (bytes, sets, pairs)."""
    raise ConstructorError(None, None, f"a value of type {node.tag.rpartition(':')[2]!r} "
                           "has no meaning here", node.start_mark)


_Loader.add_constructor("tag:yaml.org,2002:int",
                        _scalar(yaml.SafeLoader.construct_yaml_int, "an integer"))
_Loader.add_constructor("tag:yaml.org,2002:float",
                        _scalar(yaml.SafeLoader.construct_yaml_float, "a number"))
_Loader.add_constructor("tag:yaml.org,2002:bool",
                        _scalar(yaml.SafeLoader.construct_yaml_bool, "true or false"))
_Loader.add_constructor("tag:yaml.org,2002:timestamp", yaml.SafeLoader.construct_scalar)
for _tag in ("binary", "set", "omap", "pairs"):
    _Loader.add_constructor(f"tag:yaml.org,2002:{_tag}", _refuse)
_Loader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_map)
_Loader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_SEQUENCE_TAG, _construct_list)


def _code(character) -> int:
    return character if isinstance(character, int) else ord(character[:1] or "\0")


def parse_yaml(source: SourceFile):
    """Parse a YAML document of any shape (``None`` when empty), within the bounds.

    Raises:
        DiagnosticError: malformed YAML, too deep or too large once expanded.
    """
    try:
        data = yaml.load(source.text, Loader=_Loader)
    except yaml.MarkedYAMLError as error:
        mark = error.problem_mark or error.context_mark
        span = Span.point(mark.line + 1, mark.column + 1) if mark else Span.point(1)
        problem = error.problem or error.context or "invalid YAML"
        hint = error.hint if isinstance(error, (TooLarge, DuplicateKey)) else \
            "check the indentation and that every ':' is followed by a space"
        raise DiagnosticError([source.error(
            "yaml-syntax", f"malformed YAML: {problem}", span, hint)]) from None
    except yaml.reader.ReaderError as error:
        line, column = source.position(error.position)
        raise DiagnosticError([source.error(
            "yaml-syntax", f"malformed YAML: character U+{_code(error.character):04X} is not allowed",
            Span.point(line, column), "YAML text is printable Unicode, tabs and line breaks")]) \
            from None
    except yaml.YAMLError as error:
        raise DiagnosticError([source.error("yaml-syntax", f"malformed YAML: {error}",
                                            Span.point(1))]) from None
    return data


def load_yaml(source: SourceFile) -> YamlMap:
    """Parse a YAML document whose top level must be a mapping.

    Raises:
        DiagnosticError: what :func:`parse_yaml` raises, or a top level that is not a
            mapping.
    """
    data = parse_yaml(source)
    if data is None:
        data = YamlMap()
    if not isinstance(data, YamlMap):
        raise DiagnosticError([source.error(
            "yaml-syntax", "a world file must be a mapping with a 'models:' list", Span.point(1),
            "start the file with 'models:'")])
    return data
