"""The outline of a mission: its declarations, vars, behaviours and states, nested as
written."""

from __future__ import annotations

from lsprotocol import types

from ..lang import ast
from .positions import to_range

Kind = types.SymbolKind
_ITEMS = {ast.TaskDecl: Kind.Variable, ast.ConstraintDecl: Kind.Variable,
          ast.Let: Kind.Constant, ast.EventDecl: Kind.Event}


def _symbol(name: ast.Name, node, kind, detail: str | None = None, children=None):
    return types.DocumentSymbol(name=name.text, kind=kind, range=to_range(node.span),
                                selection_range=to_range(name.span), detail=detail,
                                children=children or None)


def _var(var: ast.VarDecl) -> types.DocumentSymbol:
    return _symbol(var.name, var, Kind.Variable, f"var: {var.kind.text}")


def _machine(items) -> list[types.DocumentSymbol]:
    found = []
    for item in items:
        if isinstance(item, ast.VarDecl):
            found.append(_var(item))
        elif isinstance(item, ast.StateDecl):
            found.append(_state(item))
    return found


def _state(state: ast.StateDecl) -> types.DocumentSymbol:
    children = []
    for region in state.regions:
        inner = _machine(region.machine.items) if region.machine is not None else []
        if region.name is None:
            children += inner
        else:
            children.append(_symbol(region.name, region, Kind.Namespace, "region", inner))
    detail = ("final" if state.final else
              f"{state.instance.behavior.text}(...)" if state.instance else
              "parallel" if state.parallel else "state")
    kind = Kind.EnumMember if state.final else Kind.Class
    return _symbol(state.name, state, kind, detail, children)


def document_symbols(tree: ast.Mission) -> list[types.DocumentSymbol]:
    """The outline of a mission's syntax tree."""
    found = []
    for item in tree.items:
        if type(item) in _ITEMS:
            detail = (f"{'task' if isinstance(item, ast.TaskDecl) else 'constraint'}: "
                      f"{item.kind.text}" if hasattr(item, "kind") else None)
            found.append(_symbol(item.name, item, _ITEMS[type(item)], detail))
        elif isinstance(item, ast.BehaviorDecl):
            found.append(_symbol(item.name, item, Kind.Function, "behavior",
                                 _machine(item.machine.items)))
        else:
            found += _machine([item])
    return found
