"""The shapes of a URDF's ``<visual>`` and ``<collision>`` elements, checked before
urdfdom reads them (it drops a shape it cannot read with a message on stderr, leaving
the link without it): a ``<geometry>`` in each, holding a shape URDF has, whose sizes
are finite numbers above zero in metres, and a ``<mesh>`` with a ``filename`` and a
``scale`` of three finite numbers. Each problem is located at the element or
attribute."""

from __future__ import annotations

import xml.etree.ElementTree as ET

from ..diagnostics import did_you_mean
from .urdf_positions import ElementPositions
from .urdf_values import finite, vector_parts

SIZES = {"box": {"size": 3}, "cylinder": {"radius": 1, "length": 1},
         "sphere": {"radius": 1}, "capsule": {"radius": 1, "length": 1}}
"""Each shape's size attributes and how many numbers each holds [m]."""
SHAPES = (*SIZES, "mesh")
_WRITTEN = ('<box size="X Y Z"/>, <cylinder radius="R" length="L"/>, '
            '<sphere radius="R"/> or <mesh filename="FILE.stl"/> (m)')


def check_geometry(link: ET.Element, positions: ElementPositions, diagnostics: list) -> None:
    """Report into ``diagnostics`` every shape of ``link`` that cannot be read."""
    source = positions.source

    def error(element: ET.Element, attribute: str | None, message: str, hint: str) -> None:
        diagnostics.append(source.error("urdf-error", message,
                                        positions.span(element, attribute), hint))

    for kind in ("visual", "collision"):
        for element in link.findall(kind):
            where = f"the <{kind}> of link '{link.get('name')}'"
            geometry = element.find("geometry")
            shape = geometry[0] if geometry is not None and len(geometry) else None
            if geometry is None:
                error(element, None, f"{where} has no <geometry>", "write one: " + _WRITTEN)
            elif shape is None:
                error(geometry, None, f"the <geometry> of {where} holds no shape",
                      "write one: " + _WRITTEN)
            elif shape.tag not in SHAPES:
                error(shape, None, f"<{shape.tag}> in {where} is not a URDF shape",
                      did_you_mean(shape.tag, SHAPES) or "shapes: " + _WRITTEN)
            elif shape.tag == "mesh":
                _mesh(shape, where, error)
            else:
                _sizes(shape, where, error)


def _sizes(shape: ET.Element, where: str, error) -> None:
    for name, count in SIZES[shape.tag].items():
        text = shape.get(name)
        parts = vector_parts(text or "") if count == 3 else [text or ""]
        numbers = [finite(part) for part in parts]
        if text is None:
            error(shape, None, f"the <{shape.tag}> of {where} has no '{name}'",
                  "write it: " + _WRITTEN)
        elif len(parts) != count or None in numbers:
            error(shape, name, f"'{name}' of the <{shape.tag}> of {where} must be "
                  f"{'three finite numbers' if count == 3 else 'a finite number'}, not "
                  f"'{text}'", "sizes are in metres, without a unit: " + _WRITTEN)
        elif min(numbers) <= 0:
            error(shape, name, f"'{name}' of the <{shape.tag}> of {where} must be above 0, "
                  f"not '{text}'", "a shape of no size has nothing to collide or show")


def _mesh(shape: ET.Element, where: str, error) -> None:
    if not shape.get("filename"):
        error(shape, None, f"the <mesh> of {where} has no 'filename'",
              'write the mesh file: <mesh filename="FILE.stl"/>')
    scale = shape.get("scale")
    if scale is not None and (len(vector_parts(scale)) != 3
                              or any(finite(part) is None for part in vector_parts(scale))):
        error(shape, "scale", f"'scale' of the <mesh> of {where} must be three finite "
              f"numbers, not '{scale}'", 'for example scale="0.001 0.001 0.001" (mm to m)')
