"""The mission language: parsing to a syntax tree, formatting back to text, units."""

from . import ast
from .formatter import format_mission
from .parser import ParseResult, mission_grammar, parse_file, parse_mission

__all__ = ["ast", "format_mission", "ParseResult", "mission_grammar", "parse_file",
           "parse_mission"]
