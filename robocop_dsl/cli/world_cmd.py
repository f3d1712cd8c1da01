"""``robocop-mission world FILE.yaml``: print a composed world (bodies, joints, groups)."""

from __future__ import annotations

import json
import math
import sys

from typing import TYPE_CHECKING

from ..diagnostics import Diagnostic, DiagnosticError, render_all
from ..sources import WORLD, kind_of, refusal

if TYPE_CHECKING:
    from ..world import World


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "world", help="print a composed world: bodies, joints, joint groups, processors",
        description="Load a world file (a path, or a name along the robots path such as "
                    "bazar/sophia.yaml) and print its composed tree.")
    parser.add_argument("file", help="world YAML file")
    parser.add_argument("--format", choices=("text", "json"), default="text")
    parser.add_argument("--mjcf", metavar="OUT.xml",
                        help="write the world's MuJoCo model (what the mujoco driver "
                             "simulates) to OUT.xml instead of printing the world")
    parser.set_defaults(command=run)


def run(args) -> int:
    """Exit 0 when the world loads, 1 when it has errors."""
    from ..world import load_world

    if kind_of(args.file) != WORLD:
        print(render_all([Diagnostic("unreadable-file", f"cannot read '{args.file}': "
                                     f"{refusal(args.file, WORLD)}", args.file, None)]),
              file=sys.stderr)
        return 1
    try:
        world = load_world(args.file)
        if args.mjcf is not None:
            return _write_mjcf(world, args.mjcf)
    except DiagnosticError as error:
        print(render_all(error.diagnostics), file=sys.stderr)
        return 1
    if args.format == "json":
        print(json.dumps(describe(world), indent=2))
    else:
        print(render_text(world))
    return 0


def _write_mjcf(world: World, path: str) -> int:
    """Write the MuJoCo model, with the physics step and servo of the world's mujoco
    driver when it has one (MuJoCo's defaults otherwise)."""
    from ..physics.model import mjcf
    from ..physics.servo import Servo
    from ..world.processors import option_default

    drivers = [p for p in world.processors.values() if p.type == "mujoco"]
    options = drivers[0].options if drivers else {}
    step = options.get("time_step", option_default("mujoco", "time_step"))
    servo = Servo.from_options(world, options) if drivers else None
    text = mjcf(world, step, servo)
    try:
        with open(path, "w", encoding="utf-8") as out:
            out.write(text)
    except OSError as error:
        print(f"robocop-mission world: error: cannot write {path}: {error}", file=sys.stderr)
        return 1
    print(f"{path}: the MuJoCo model of {world.path.name}")
    return 0


def _finite(values) -> list:
    return [v if math.isfinite(v) else None for v in map(float, values)]


def placements(world: World) -> dict:
    """Each body's world ``(position [m], rpy [rad])`` at the initial configuration."""
    from ..world.placement import rpy_of

    poses = world.body_placements(world.initial_configuration())
    return {name: ([float(v) + 0.0 for v in pose.translation],
                   [v + 0.0 for v in rpy_of(pose.rotation)])
            for name, pose in poses.items()}


def describe(world: World) -> dict:
    """The world as plain data: SI units, ``None`` where unlimited, body placements in
    the world frame at the initial configuration."""
    where = placements(world)
    return {
        "path": str(world.path),
        "units": {"position": "m", "rpy": "rad"},
        "bodies": [{"name": b, "parent": world.body(b).parent, "joint": world.body(b).joint,
                    "position": where[b][0], "rpy": where[b][1]}
                   for b in world.body_names()],
        "joints": [{"name": j.name, "type": j.type, "parent": j.parent, "child": j.child,
                    "dofs": j.dofs, "lower": _finite(j.lower), "upper": _finite(j.upper),
                    "max_velocity": _finite(j.max_velocity), "mimic": j.mimic}
                   for j in map(world.joint, world.joint_names())],
        "joint_groups": [{"name": g, "dofs": world.joint_group(g).dofs,
                          "joints": list(world.joint_group(g).joints)}
                         for g in world.group_names()],
        "processors": [{"name": p.name, "type": p.type,
                        "options": {**p.options, **p.run_options}, "driver": p.driver}
                       for p in world.processors.values()],
        "physics": {"gravity": list(world.physics.gravity),
                    "friction": list(world.physics.friction),
                    "free_bodies": world.free_bodies()},
        "collisions": collisions(world),
    }


def collisions(world: World) -> dict:
    """The collision bodies with their shapes, and the pairs of bodies a collision check
    may cover (adjacent, allowed and rigidly joined pairs left out)."""
    from ..world.collisions import collision_geometry, describe_shape, world_pairs

    geometry = collision_geometry(world)
    return {"bodies": [{"name": body, "shapes": [describe_shape(s) for s in shapes]}
                       for body, shapes in geometry.by_body.items()],
            "checked_pairs": [list(pair) for pair in world_pairs(world)],
            "allowed": sorted(sorted(pair) for pair in world.allowed_collisions)}


def _limits(joint) -> str:
    if not joint.dofs:
        return f"mimics {joint.mimic}" if joint.mimic else ""
    unit, scale, digits = (("m", 1.0, 3) if joint.type == "prismatic"
                           else ("deg", 180 / math.pi, 1))
    low, high, speed = (float(value) * scale for value in
                        (joint.lower[0], joint.upper[0], joint.max_velocity[0]))
    span = (f"[{low:.{digits}f}, {high:.{digits}f}] {unit}"
            if math.isfinite(low) and math.isfinite(high) else "unbounded")
    rate = f", {speed:.{digits}f} {unit}/s" if math.isfinite(speed) else ""
    return span + rate


def _numbers(values, digits: int) -> str:
    """``[a, b, c]`` rounded to ``digits`` decimals, without negative zeros."""
    return "[" + ", ".join(f"{round(v, digits) + 0.0:.{digits}f}" for v in values) + "]"


def _placement(position: list, rpy: list) -> str:
    return f"{_numbers(position, 3)} {_numbers(map(math.degrees, rpy), 1)}"


def render_text(world: World) -> str:
    """A readable listing: the body tree, the moving joints, groups and processors."""
    children: dict = {}
    for name in world.body_names():
        children.setdefault(world.body(name).parent, []).append(name)
    where = placements(world)
    lines = [f"world {world.path}", "",
             f"bodies ({len(world.body_names())}), world placement at the initial "
             "configuration as position [m], rpy [deg]:"]

    def walk(name: str, depth: int) -> None:
        joint = world.body(name).joint
        kind = f"  ({world.joint(joint).type} {joint})" if joint else ""
        lines.append(f"  {'  ' * depth}{name}{kind}  {_placement(*where[name])}")
        for child in children.get(name, []):
            walk(child, depth + 1)

    walk("world", 0)
    moving = [world.joint(j) for j in world.joint_names() if world.joint(j).type != "fixed"]
    lines += ["", f"joints ({len(moving)} moving, {len(world.joint_names())} in all):"]
    width = max((len(j.name) for j in moving), default=0)
    lines += [f"  {j.name:<{width}}  {j.type:<10} {_limits(j)}" for j in moving]
    lines += ["", "joint groups:"]
    for name in world.group_names():
        group = world.joint_group(name)
        lines.append(f"  {name}: {group.dofs} dofs ({', '.join(group.joints)})")
    lines += ["", "processors:"]
    for processor in world.processors.values():
        options = ", ".join(f"{k}: {v}" for k, v in {**processor.options,
                                                      **processor.run_options}.items())
        driver = f" (driver: {processor.driver})" if processor.driver else ""
        lines.append(f"  {processor.name}: {processor.type} {{{options}}}{driver}")
    physics = world.physics
    lines += ["", f"physics: gravity {list(physics.gravity)} m/s^2, friction "
                  f"{list(physics.friction)} (sliding, torsional m, rolling m), free bodies: "
                  f"{', '.join(world.free_bodies()) or 'none'}"]
    lines += _collision_lines(collisions(world))
    return "\n".join(lines)


def _collision_lines(found: dict) -> list:
    lines = ["", f"collision bodies ({len(found['bodies'])}):"]
    lines += [f"  {body['name']}: {', '.join(body['shapes'])}" for body in found["bodies"]]
    partners: dict = {}
    for first, second in found["checked_pairs"]:
        partners.setdefault(first, []).append(second)
    lines += ["", f"checked pairs ({len(found['checked_pairs'])}; adjacent bodies, bodies "
              f"that no joint moves apart and {len(found['allowed'])} allowed pairs left out):"]
    lines += [f"  {body}: {', '.join(others)}" for body, others in partners.items()]
    return lines
