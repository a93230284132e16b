"""Strict typed configs: round trips, conversions, unknown keys with did-you-mean, ranges."""
import dataclasses
import typing
from dataclasses import dataclass, field
from typing import ClassVar

import pytest

from slam_predict.config import (
    AT_LEAST_ONE,
    NON_NEGATIVE,
    POSITIVE,
    PROBABILITY,
    Range,
    check_keys,
    config_hash,
    from_dict,
    load_config,
    to_dict,
)
from slam_predict.errors import InputError


@dataclass
class Inner:
    gain: float = 1.0
    name: str = "x"


@dataclass
class Outer:
    particles: int = 30
    bounds: tuple[float, float] = (0.0, 1.0)
    inner: Inner = field(default_factory=Inner)
    optional: float | None = None
    flag: bool = False


def test_round_trip():
    cfg = Outer(particles=40, bounds=(0.5, 2.0), inner=Inner(3.0, "y"), optional=1.5, flag=True)
    assert from_dict(Outer, to_dict(cfg)) == cfg


def test_ints_become_floats_and_lists_tuples():
    cfg = from_dict(Outer, {"bounds": [1, 2], "inner": {"gain": 2}})
    assert cfg.bounds == (1.0, 2.0) and isinstance(cfg.inner.gain, float)


# Both spellings of an optional field: ``typing.Optional[X]`` (a typing.Union) and ``X | None``
# (a types.UnionType, what ruff's pyupgrade rules write); built at run time so the linter keeps
# the old spelling.
OPTIONAL_SPELLINGS = {"typing.Optional": (typing.Optional[float],  # noqa: UP045
                                          typing.Optional[tuple[float, float]]),  # noqa: UP045
                      "X | None": (float | None, tuple[float, float] | None)}


@pytest.mark.parametrize("spelling", sorted(OPTIONAL_SPELLINGS))
def test_both_optional_spellings_convert_alike(spelling):
    number, pair = OPTIONAL_SPELLINGS[spelling]
    cls = dataclasses.make_dataclass("Optionals", [("limit", number, None), ("pair", pair, None)])
    cfg = from_dict(cls, {"limit": 2, "pair": [1, 2]})
    assert (cfg.limit, cfg.pair) == (2.0, (1.0, 2.0)) and isinstance(cfg.limit, float)
    assert from_dict(cls, {"limit": None}).limit is None
    with pytest.raises(InputError, match="must be a number"):
        from_dict(cls, {"limit": "far"})


def test_unknown_key_did_you_mean():
    with pytest.raises(InputError) as info:
        from_dict(Outer, {"particle": 3}, "cfg.yaml")
    message = str(info.value)
    assert message.startswith("cfg.yaml: unknown config key 'particle'")
    assert "did you mean 'particles'" in message


def test_nested_unknown_key_and_types():
    with pytest.raises(InputError, match="unknown config key 'gian'.*did you mean 'gain'"):
        from_dict(Outer, {"inner": {"gian": 1}})
    with pytest.raises(InputError, match="must be an integer"):
        from_dict(Outer, {"particles": 2.5})
    with pytest.raises(InputError, match="needs 2 values"):
        from_dict(Outer, {"bounds": [1, 2, 3]})
    with pytest.raises(InputError, match="true or false"):
        from_dict(Outer, {"flag": "yes"})


def test_load_config_file_errors(tmp_path):
    good = tmp_path / "good.yaml"
    good.write_text("particles: 12\ninner:\n  name: z\n")
    assert load_config(Outer, good).particles == 12
    bad = tmp_path / "bad.yaml"
    bad.write_text("particles: [1,\n")
    with pytest.raises(InputError) as info:
        load_config(Outer, bad)
    assert str(bad) in str(info.value) and "YAML syntax error" in str(info.value)
    with pytest.raises(InputError, match="config file not found"):
        load_config(Outer, tmp_path / "missing.yaml")


def test_config_hash_stable_and_sensitive():
    assert config_hash(Outer()) == config_hash(Outer())
    assert config_hash(Outer()) != config_hash(Outer(particles=31))


@dataclass
class Ranged:
    count: int = 1
    rate: float = 1.0
    share: float = 0.5
    gains: tuple[float, ...] = (1.0,)
    limit: float | None = None
    RANGES: ClassVar[dict[str, Range]] = {"count": AT_LEAST_ONE, "rate": POSITIVE,
                                          "share": PROBABILITY, "gains": NON_NEGATIVE,
                                          "limit": NON_NEGATIVE}


@dataclass
class Holder:
    ranged: Ranged = field(default_factory=Ranged)


@pytest.mark.parametrize("data,message", [
    ({"count": 0}, "'ranged.count' must be ≥ 1, got 0"),
    ({"rate": 0.0}, "'ranged.rate' must be > 0, got 0.0"),
    ({"share": 1.5}, "'ranged.share' must be in [0, 1], got 1.5"),
    ({"share": -0.1}, "'ranged.share' must be in [0, 1], got -0.1"),
    ({"gains": [1.0, -2.0]}, "'ranged.gains' must be ≥ 0, got -2.0"),
    ({"limit": float("nan")}, "'ranged.limit' must be ≥ 0, got nan"),
    ({"cuont": 3}, "unknown config key 'cuont' in 'ranged' (did you mean 'count'?)"),
])
def test_nested_values_out_of_range_name_file_key_and_range(data, message):
    with pytest.raises(InputError) as info:
        from_dict(Holder, {"ranged": data}, "cfg.yaml")
    assert info.value.one_line() == f"cfg.yaml: {message}"


def test_values_in_range_and_unset_optionals_pass():
    cfg = from_dict(Holder, {"ranged": {"count": 1, "rate": 1e-9, "share": 1, "gains": [0, 2],
                                        "limit": None}})
    assert cfg.ranged.share == 1.0 and cfg.ranged.limit is None


@pytest.mark.parametrize("allowed,inside,outside", [
    (Range(0.0), [0.0, 5.0], [-1e-9]),
    (Range(0.0, open_low=True), [1e-9], [0.0, -1.0]),
    (Range(0.0, 1.0, open_low=True, open_high=True), [0.5], [0.0, 1.0]),
    (Range(high=2.0), [-5.0, 2.0], [2.1]),
])
def test_range_bounds(allowed, inside, outside):
    assert all(allowed.contains(v) for v in inside)
    assert not any(allowed.contains(v) for v in outside)
    assert not allowed.contains(float("nan"))


def test_range_descriptions():
    assert Range(0.0).describe() == "≥ 0"
    assert Range(0.0, open_low=True).describe() == "> 0"
    assert Range(0.0, 1.0, open_low=True, open_high=True).describe() == "in (0, 1)"
    assert Range(high=2.0, open_high=True).describe() == "< 2"


def test_section_file_rejects_other_top_level_keys(tmp_path):
    path = tmp_path / "robot.yaml"
    path.write_text("sim:\n  particles: 3\nsimm: {}\n")
    with pytest.raises(InputError, match=r"unknown config key 'simm' \(did you mean 'sim'\?\)"):
        load_config(Outer, path, "sim")
    path.write_text("particles: 3\n")   # settings not under the section: not silently ignored
    with pytest.raises(InputError, match="unknown config key 'particles' \\(expected 'sim'\\)"):
        load_config(Outer, path, "sim")
    path.write_text("sim: 3\n")
    with pytest.raises(InputError, match="'sim' must be a mapping"):
        load_config(Outer, path, "sim")
    path.write_text("sim:\n  particles: 3\n")
    assert load_config(Outer, path, "sim").particles == 3


def test_check_keys():
    check_keys({"a": 1}, ("a", "b"), "f.yaml")
    with pytest.raises(InputError, match="f.yaml: unknown config key 'c' in 'top'"):
        check_keys({"c": 1}, ("a", "b"), "f.yaml", "top")


def _config_classes():
    """Every dataclass of the project's config modules that declares RANGES."""
    import importlib

    modules = ["slam_predict.sim.config", "slam_predict.nav.config",
               "slam_predict.slam.gmapping.params", "slam_predict.learn.config",
               "slam_predict.ros.orchestrator_config", "slam_predict.ros.ground_truth",
               "slam_predict.ros.orchestrator", "slam_predict.features.vector",
               "slam_predict.features.rooms", "slam_predict.features.traversal",
               "slam_predict.features.topology", "slam_predict.features.geometric",
               "slam_predict.features.voronoi", "slam_predict.explore.run",
               "slam_predict.collect.stopping"]
    found = {}
    for name in modules:
        for obj in vars(importlib.import_module(name)).values():
            if isinstance(obj, type) and dataclasses.is_dataclass(obj) and "RANGES" in vars(obj):
                found[obj.__name__] = obj
    return found


def test_declared_ranges_name_fields_and_admit_the_defaults():
    classes = _config_classes()
    assert len(classes) >= 20
    for cls in classes.values():
        names = {f.name for f in dataclasses.fields(cls)}
        assert set(cls.RANGES) <= names, cls.__name__
        default = cls()
        for key, allowed in cls.RANGES.items():
            value = getattr(default, key)
            for item in value if isinstance(value, tuple) else (value,):
                assert item is None or allowed.contains(item), (cls.__name__, key, item)
        assert from_dict(cls, to_dict(default)) == default
