"""Reading a campaign file into a :class:`CampaignSpec`, every problem a located
diagnostic (file, line, column, hint), all of them reported at once.

This pass checks the file's shape only; names of bodies, joints, missions and worlds
are checked against the worlds by :mod:`.checker`.
"""

from __future__ import annotations

import math
from pathlib import Path

from ..diagnostics import DiagnosticError, SourceFile, Span, did_you_mean, sort_key
from ..sources import not_a_file
from ..world.description import to_seconds
from ..world.processors import SHORTEST
from ..world.yaml_source import YamlList, YamlMap, parse_yaml
from .spec import SETTINGS, BodyMove, CampaignSpec, MissionEntry, Normal, PhysicsNoise, \
    PostureNoise, Uniform, VariantEntry, Where

TOP_KEYS = ("campaign", "description", "missions", "variants", "settings", "samples",
            "seed", "duration", "time_budget", "vary")
MISSION_KEYS = ("path", "duration", "time_budget")
VARY_KEYS = ("bodies", "initial_posture", "physics")
PHYSICS_KEYS = ("friction", "mass")
BODY_KEYS = ("move", "uniform", "normal")
POSTURE_KEYS = ("joints", "uniform", "normal")
HIERARCHIES = ("strict", "weighted")
MAX_SAMPLES = 100_000
"""Samples a campaign draws at most per mission, variant and setting."""
MAX_JOBS = 1_000_000
"""Jobs a campaign expands into at most (missions x variants x settings x samples)."""
MAX_DURATION = 86_400.0
"""The longest ``duration`` or ``time_budget`` [s]: a day."""


def read_campaign(path: str | Path) -> CampaignSpec:
    """Read and shape-check the campaign file at ``path``.

    Raises:
        DiagnosticError: every problem found, each located in the file.
    """
    path = Path(path)
    problem = not_a_file(path)
    if problem:
        raise DiagnosticError([SourceFile(str(path), "").error(
            "unreadable-file", f"cannot read campaign file '{path}': {problem}", None)])
    source = SourceFile.read(path)
    reader = _Reader(source)
    spec = reader.campaign(_load(source), path.resolve())
    if reader.diagnostics:
        raise DiagnosticError(sorted(reader.diagnostics, key=sort_key))
    return spec


def _load(source: SourceFile) -> YamlMap:
    data = parse_yaml(source)
    if data is None or isinstance(data, YamlMap):
        return data if data is not None else YamlMap()
    raise DiagnosticError([source.error(
        "not-a-campaign", "a campaign file must be a mapping with a 'missions:' list", Span.point(1),
        "start the file with 'missions:'")])


class _Reader:
    """Walks the YAML tree; each helper returns ``None`` after recording a problem."""

    def __init__(self, source: SourceFile):
        self.source = source
        self.diagnostics: list = []

    def where(self, span: Span) -> Where:
        return Where(self.source, span)

    def error(self, code: str, message: str, span: Span, hint: str | None = None) -> None:
        self.diagnostics.append(self.source.error(code, message, span, hint))

    def keys(self, mapping: YamlMap, allowed: tuple) -> None:
        for key in mapping:
            if key not in allowed:
                self.error("unknown-key", f"unknown key '{key}'", mapping.span(key),
                           did_you_mean(str(key), allowed)
                           or "expected one of: " + ", ".join(allowed))

    def campaign(self, data: YamlMap, path: Path) -> CampaignSpec:
        self.keys(data, TOP_KEYS)
        if "missions" not in data:
            self.error("missing-key", "a campaign needs a 'missions:' list", data.span(),
                       "add 'missions: [my.mission]' (paths relative to this file)")
        vary = self.mapping(data, "vary") or YamlMap()
        self.keys(vary, VARY_KEYS)
        settings, settings_where = self.settings(data)
        name = self.name(data, path.name.split(".")[0])
        return CampaignSpec(
            name=name, path=path, description=self.string(data, "description", ""),
            missions=tuple(self.missions(data)), variants=tuple(self.variants(data)),
            settings=settings, samples=self.samples(data, settings),
            seed=self.integer(data, "seed", 0, minimum=0),
            duration=self.duration(data, "duration"),
            time_budget=self.duration(data, "time_budget"),
            bodies=tuple(self.entries(vary, "bodies", self.body_move)),
            postures=tuple(self.entries(vary, "initial_posture", self.posture)),
            physics=self.physics(vary), settings_where=settings_where)

    def string(self, mapping: YamlMap, key: str, default: str) -> str:
        if key not in mapping:
            return default
        value = mapping[key]
        if not isinstance(value, str) or not value:
            self.error("wrong-value", f"'{key}' must be a non-empty string", mapping.value_span(key))
            return default
        return value

    def name(self, data: YamlMap, default: str) -> str:
        """``campaign``: it names the default results file, so it is a file name."""
        name = self.string(data, "campaign", default)
        if name == default:
            return name
        if name in (".", "..") or any(c in "/\\" or not c.isprintable() for c in name):
            self.error("wrong-value", f"campaign name {name!r} cannot name a file",
                       data.value_span("campaign"), "no '/', '\\' or control "
                       "character, and not '.' or '..': e.g. 'pickup_workbench'")
            return default
        return name

    def samples(self, data: YamlMap, settings: dict) -> int:
        """``samples``, at most :data:`MAX_SAMPLES`, and the jobs they make at most
        :data:`MAX_JOBS`."""
        samples = self.integer(data, "samples", 1, minimum=1)
        if samples > MAX_SAMPLES:
            self.error("wrong-value", f"'samples' is {samples:,}: at most {MAX_SAMPLES:,}",
                       data.value_span("samples"), "split the campaign, or draw fewer "
                       "samples: the success rate's interval narrows as 1/sqrt(samples)")
            return 1
        missions = _count(data.get("missions"))
        variants = _count(data.get("variants"))
        combinations = 1
        for values in settings.values():
            combinations *= max(len(values), 1)
        jobs = missions * variants * combinations * samples
        if jobs > MAX_JOBS:
            self.error("wrong-value", f"the campaign makes {jobs:,} jobs: at most "
                       f"{MAX_JOBS:,}", data.value_span("samples"),
                       "fewer samples, settings, variants or missions per campaign")
            return 1
        return samples

    def integer(self, mapping: YamlMap, key: str, default: int, minimum: int) -> int:
        value = mapping.get(key, default)
        if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
            self.error("wrong-value", f"'{key}' must be an integer >= {minimum}",
                       mapping.value_span(key))
            return default
        return value

    def duration(self, mapping: YamlMap, key: str) -> float | None:
        if key not in mapping:
            return None
        value = to_seconds(mapping[key])
        if isinstance(value, bool) or not isinstance(value, (int, float)) or value <= 0:
            self.error("wrong-value", f"'{key}' must be a positive duration",
                       mapping.value_span(key), "write seconds, e.g. '30 s', '500 ms' or 12.5")
            return None
        if not value <= MAX_DURATION:
            self.error("wrong-value", f"'{key}' must be at most a day ({MAX_DURATION:g} s), "
                       f"not {value:g} s", mapping.value_span(key),
                       "a run is bounded: write its mission time, e.g. '120 s'")
            return None
        return float(value)

    def mapping(self, data: YamlMap, key: str) -> YamlMap | None:
        value = data.get(key)
        if value is None or isinstance(value, YamlMap):
            return value
        self.error("wrong-value", f"'{key}' must be a mapping", data.value_span(key))
        return None

    def listing(self, data: YamlMap, key: str) -> YamlList:
        value = data.get(key)
        if value is None:
            return YamlList()
        if not isinstance(value, YamlList):
            self.error("wrong-value", f"'{key}' must be a list", data.value_span(key))
            return YamlList()
        return value

    def missions(self, data: YamlMap) -> list:
        items = self.listing(data, "missions")
        if "missions" in data and isinstance(data["missions"], YamlList) and not items:
            self.error("missing-key", "'missions' is empty", data.value_span("missions"))
        result = []
        for index, item in enumerate(items):
            where = self.where(items.span(index))
            if isinstance(item, str):
                result.append(MissionEntry(Path(item), where))
            elif isinstance(item, YamlMap) and isinstance(item.get("path"), str):
                self.keys(item, MISSION_KEYS)
                result.append(MissionEntry(Path(item["path"]), self.where(item.value_span("path")),
                                           self.duration(item, "duration"),
                                           self.duration(item, "time_budget")))
            else:
                self.error("wrong-value", "a mission is a path, or a mapping with 'path:'",
                           items.span(index), "e.g. '- pickup.mission'")
        return result

    def variants(self, data: YamlMap) -> list:
        variants = self.mapping(data, "variants") or YamlMap()
        result = []
        for name, world in variants.items():
            if not isinstance(world, str):
                self.error("wrong-value", f"variant '{name}' must name a world file",
                           variants.value_span(name), "e.g. 'low_bench: bazar/low_bench.yaml'")
                continue
            result.append(VariantEntry(str(name), world, self.where(variants.value_span(name))))
        return result

    def settings(self, data: YamlMap) -> tuple:
        settings = self.mapping(data, "settings") or YamlMap()
        self.keys(settings, SETTINGS)
        values, where = {}, {}
        for key in SETTINGS:
            if key not in settings:
                continue
            raw = settings[key]
            items = list(raw) if isinstance(raw, YamlList) else [raw]
            spans = ([raw.span(i) for i in range(len(raw))] if isinstance(raw, YamlList)
                     else [settings.value_span(key)])
            checked = [self.setting(key, item, span) for item, span in zip(items, spans)]
            if not items:
                self.error("wrong-value", f"'{key}' lists no value", settings.value_span(key))
            values[key] = tuple(checked)
            where[key] = tuple(self.where(span) for span in spans)
        return values, where

    def setting(self, key: str, value, span: Span):
        if key == "time_step":
            seconds = to_seconds(value)
            if isinstance(seconds, bool) or not isinstance(seconds, (int, float)) or seconds <= 0:
                self.error("wrong-value", "'time_step' must be a positive duration", span,
                           "e.g. '5ms'")
            elif not _finite(seconds):
                self.error("wrong-value", "'time_step' must be finite", span, "e.g. '5ms'")
            elif seconds < SHORTEST:
                self.error("wrong-value", f"'time_step' must be at least {SHORTEST * 1e6:g}us, "
                           f"not {value}", span, "a time step that short is a typo (5ms, 250us)")
            return seconds
        if key == "hierarchy" and value not in HIERARCHIES:
            self.error("unknown-hierarchy", f"unknown hierarchy '{value}'", span,
                       did_you_mean(str(value), HIERARCHIES) or "use 'strict' or 'weighted'")
        elif not isinstance(value, str):
            self.error("wrong-value", f"'{key}' must be a name", span)
        return value

    def entries(self, vary: YamlMap, key: str, read) -> list:
        items = self.listing(vary, key)
        result = []
        for index, item in enumerate(items):
            if not isinstance(item, YamlMap):
                self.error("wrong-value", f"each '{key}' entry must be a mapping", items.span(index))
                continue
            entry = read(item, self.where(items.span(index)))
            if entry is not None:
                result.append(entry)
        return result

    def body_move(self, item: YamlMap, where: Where) -> BodyMove | None:
        self.keys(item, BODY_KEYS)
        bodies = item.get("move")
        if isinstance(bodies, str):
            names, spans = (bodies,), (item.value_span("move"),)
        elif isinstance(bodies, YamlList) and bodies and all(isinstance(b, str) for b in bodies):
            names, spans = tuple(bodies), tuple(bodies.span(i) for i in range(len(bodies)))
        else:
            self.error("wrong-value", "'move' must name a body or list bodies", item.span("move"),
                       "e.g. 'move: [pickup_point, part_body]'")
            return None
        distribution = self.distribution(item, where, size=3, absolute=True)
        return distribution and BodyMove(names, distribution, where, spans)

    def posture(self, item: YamlMap, where: Where) -> PostureNoise | None:
        self.keys(item, POSTURE_KEYS)
        joints = item.get("joints")
        if not isinstance(joints, str):
            self.error("wrong-value", "'joints' must name a joint group or a joint",
                       item.span("joints"), "e.g. 'joints: bazar_arms'")
            return None
        distribution = self.distribution(item, where, size=None, absolute=False)
        return distribution and PostureNoise(joints, distribution,
                                             self.where(item.value_span("joints")))

    def physics(self, vary: YamlMap) -> PhysicsNoise:
        """``vary: physics: {friction: DISTRIBUTION, mass: {BODY: DISTRIBUTION}}``."""
        physics = self.mapping(vary, "physics")
        if physics is None:
            return PhysicsNoise()
        self.keys(physics, PHYSICS_KEYS)
        friction = None
        if "friction" in physics:
            friction = self.scalar(physics, "friction")
        masses, spans = [], []
        for body, value in (self.mapping(physics, "mass") or YamlMap()).items():
            distribution = self.scalar(physics["mass"], body)
            if distribution is not None:
                masses.append((str(body), distribution))
                spans.append(physics["mass"].span(body))
        return PhysicsNoise(friction, tuple(masses), self.where(vary.span("physics")),
                            tuple(spans))

    def scalar(self, mapping: YamlMap, key):
        """A one-number distribution written ``KEY: {uniform: ...}`` or ``{normal: ...}``,
        every value > 0 where a uniform draws."""
        value = mapping[key]
        if not isinstance(value, YamlMap):
            self.error("wrong-value", f"'{key}' must be a mapping with 'uniform:' or "
                       "'normal:'", mapping.value_span(key), "e.g. '{uniform: {low: 0.4, "
                       "high: 1.2}}'")
            return None
        self.keys(value, ("uniform", "normal"))
        distribution = self.distribution(value, self.where(mapping.span(key)), size=1,
                                         absolute=True)
        if isinstance(distribution, Uniform) and min(distribution.low) <= 0:
            self.error("wrong-value", f"'{key}' must stay > 0: 'low' is "
                       f"{min(distribution.low):g}", value.span("uniform"))
            return None
        return distribution

    def distribution(self, item: YamlMap, where: Where, size, absolute: bool):
        kinds = [k for k in ("uniform", "normal") if k in item]
        if len(kinds) != 1:
            self.error("missing-key", "give exactly one of 'uniform:' or 'normal:'", where.span)
            return None
        kind = kinds[0]
        value = item[kind]
        if not isinstance(value, YamlMap):
            self.error("wrong-value", f"'{kind}' must be a mapping", item.value_span(kind),
                       "e.g. '{low: [0.6, 0.1, 0.76], high: [0.8, 0.3, 0.76]}'" if kind ==
                       "uniform" else "e.g. '{std: 0.02}'")
            return None
        if kind == "uniform":
            self.keys(value, ("low", "high"))
            low, high = self.vector(value, "low", size), self.vector(value, "high", size)
            if low is not None and high is not None and _descending(low, high):
                self.error("wrong-value", "'low' must not exceed 'high'", value.value_span("low"))
            return None if low is None or high is None else Uniform(low, high)
        self.keys(value, ("std", "mean") if absolute else ("std",))
        std = self.vector(value, "std", size)
        if std is not None and any(s < 0 for s in std):
            self.error("wrong-value", "'std' must not be negative", value.value_span("std"))
        mean = self.vector(value, "mean", size) if "mean" in value else None
        return None if std is None else Normal(std, mean)

    def vector(self, mapping: YamlMap, key: str, size) -> tuple | None:
        """A number (broadcast later) or a list of numbers; ``size`` when fixed."""
        if key not in mapping:
            self.error("missing-key", f"missing '{key}'", mapping.span())
            return None
        value = mapping[key]
        items = list(value) if isinstance(value, YamlList) else [value]
        if not all(_is_number(v) for v in items) or not items:
            self.error("wrong-value", f"'{key}' must be a number or a list of numbers",
                       mapping.value_span(key))
            return None
        if not all(_finite(v) for v in items):
            self.error("wrong-value", f"'{key}' must be finite", mapping.value_span(key),
                       "a number within the float range, not .nan or .inf")
            return None
        if size is not None and len(items) not in (1, size):
            self.error("wrong-value", f"'{key}' needs {size} values (x, y, z in metres)"
                       if size == 3 else f"'{key}' is one number", mapping.value_span(key))
            return None
        if size is not None and len(items) == 1:
            items = items * size
        return tuple(float(v) for v in items)


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _finite(value) -> bool:
    """Whether the number ``value`` is finite as a float."""
    try:
        return math.isfinite(value)
    except OverflowError:
        return False


def _count(value) -> int:
    """Entries of a list or mapping, 1 for anything else (reported elsewhere)."""
    return max(len(value), 1) if isinstance(value, (YamlList, YamlMap)) else 1


def _descending(low: tuple, high: tuple) -> bool:
    """Whether some ``low`` exceeds its ``high`` (a single value pairs with every other)."""
    low = low * len(high) if len(low) == 1 else low
    high = high * len(low) if len(high) == 1 else high
    return len(low) == len(high) and any(a > b for a, b in zip(low, high))
