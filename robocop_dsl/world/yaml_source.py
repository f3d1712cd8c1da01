"""YAML reading that keeps where every key and item came from (1-based lines)."""

from __future__ import annotations

import yaml

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


class _Loader(yaml.SafeLoader):
    pass


def _construct_map(loader: _Loader, node) -> YamlMap:
    loader.flatten_mapping(node)
    result = YamlMap()
    result.line, result.column = node.start_mark.line + 1, node.start_mark.column + 1
    for key_node, value_node in node.value:
        key = loader.construct_object(key_node, deep=True)
        result[key] = loader.construct_object(value_node, deep=True)
        result.key_spans[key] = _span(key_node)
        result.value_spans[key] = _span(value_node)
    return result


def _construct_list(loader: _Loader, node) -> YamlList:
    result = YamlList()
    result.line, result.column = node.start_mark.line + 1, node.start_mark.column + 1
    for item in node.value:
        result.append(loader.construct_object(item, deep=True))
        result.item_spans.append(_span(item))
    return result


_Loader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_map)
_Loader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_SEQUENCE_TAG, _construct_list)


def load_yaml(source: SourceFile) -> YamlMap:
    """Parse a YAML document whose top level must be a mapping.

    Raises:
        DiagnosticError: malformed YAML or a top level that is not a mapping.
    """
    try:
        data = yaml.load(source.text, Loader=_Loader)
    except yaml.MarkedYAMLError as error:
        mark = error.problem_mark or error.context_mark
        span = Span.point(mark.line + 1, mark.column + 1) if mark else None
        problem = error.problem or error.context or "invalid YAML"
        raise DiagnosticError([source.error(
            "yaml-syntax", f"malformed YAML: {problem}", span,
            "check the indentation and that every ':' is followed by a space")]) from None
    except yaml.YAMLError as error:
        raise DiagnosticError([source.error("yaml-syntax", f"malformed YAML: {error}", None)]) from None
    if data is None:
        data = YamlMap()
    if not isinstance(data, YamlMap):
        raise DiagnosticError([source.error(
            "yaml-syntax", "a world file must be a mapping with a 'models:' list", Span.point(1),
            "start the file with 'models:'")])
    return data
