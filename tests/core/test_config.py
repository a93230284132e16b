"""Strict typed configs: round trips, conversions, unknown keys with did-you-mean."""
from dataclasses import dataclass, field
from typing import Optional, Tuple

import pytest

from slam_predict.config import config_hash, from_dict, load_config, to_dict
from slam_predict.errors import InputError


@dataclass
class Inner:
    gain: float = 1.0
    name: str = "x"


@dataclass
class Outer:
    particles: int = 30
    bounds: Tuple[float, float] = (0.0, 1.0)
    inner: Inner = field(default_factory=Inner)
    optional: Optional[float] = None
    flag: bool = False


def test_round_trip():
    cfg = Outer(particles=40, bounds=(0.5, 2.0), inner=Inner(3.0, "y"), optional=1.5, flag=True)
    assert from_dict(Outer, to_dict(cfg)) == cfg


def test_ints_become_floats_and_lists_tuples():
    cfg = from_dict(Outer, {"bounds": [1, 2], "inner": {"gain": 2}})
    assert cfg.bounds == (1.0, 2.0) and isinstance(cfg.inner.gain, float)


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
