"""slam_gmapping parameters: defaults, strict YAML loading, the baseline files as they are."""
import pytest
import yaml

from slam_predict.errors import InputError
from slam_predict.slam.gmapping.params import (
    GMappingParams,
    load_params,
    params_from_dict,
    params_from_record,
    params_to_dict,
    resolve_ranges,
)


def test_defaults_are_slam_gmappings():
    p = GMappingParams()
    assert (p.particles, p.linearUpdate, p.angularUpdate, p.temporalUpdate) == (30, 1.0, 0.5, -1.0)
    assert (p.srr, p.srt, p.str, p.stt) == (0.1, 0.2, 0.1, 0.2)
    assert (p.sigma, p.kernelSize, p.lstep, p.astep, p.iterations) == (0.05, 1, 0.05, 0.05, 5)
    assert (p.lsigma, p.ogain, p.lskip, p.minimumScore) == (0.075, 3.0, 0, 0.0)
    assert (p.xmin, p.ymin, p.xmax, p.ymax, p.delta, p.occ_thresh) == (-100, -100, 100, 100,
                                                                       0.05, 0.25)
    assert p.map_update_interval == 5.0 and p.effective_tf_delay == 0.05
    assert p.reproduce_freecell_bug is True
    assert p.random_stream == "drand48" and p.drand48_seed is None


@pytest.mark.parametrize("log", ["intel", "aces", "csail", "freiburg-101", "freiburg-079"])
def test_baseline_yamls_load_as_is(shared_dir, log):
    path = shared_dir / "baselines" / f"gmapping_real_{log}.yaml"
    written = yaml.safe_load(path.read_text())
    loaded = params_to_dict(load_params(path))
    assert {"particles", "maxRange", "maxUrange"} <= written.keys()
    assert {key: loaded[key] for key in written} == written


def test_thesis_config_values(root):
    p = load_params(root / "config" / "gmapping.yaml")
    assert p.particles == 40
    assert (p.linearUpdate, p.angularUpdate, p.temporalUpdate) == (1.0, 0.25, 5.0)
    assert (p.maxUrange, p.maxRange, p.delta) == (30.0, 60.0, 0.05)
    assert (p.srr, p.srt, p.str, p.stt) == (0.01, 0.02, 0.01, 0.02)


def test_unknown_key_is_rejected_with_a_hint():
    with pytest.raises(InputError, match="did you mean 'linearUpdate'"):
        params_from_dict({"linearupdate": 1.0}, "x.yaml")


def test_wrong_type_and_bad_values_are_input_errors():
    with pytest.raises(InputError, match="particles"):
        params_from_dict({"particles": "many"}, "x.yaml")
    with pytest.raises(InputError, match="'particles' must be ≥ 1, got 0"):
        params_from_dict({"particles": 0}, "x.yaml")
    with pytest.raises(InputError, match="not gmapping"):
        params_from_dict({"type": "karto"}, "x.yaml")


def test_ranges_follow_the_first_scan_when_unset():
    assert resolve_ranges(GMappingParams(), 30.0) == (29.99, 29.99)
    assert resolve_ranges(GMappingParams(maxUrange=10.0), 30.0) == (29.99, 10.0)
    assert resolve_ranges(GMappingParams(maxRange=60.0, maxUrange=30.0), float("nan")) == (60, 30)
    with pytest.raises(ValueError):
        resolve_ranges(GMappingParams(), float("nan"))


def test_random_stream_options_are_checked():
    p = params_from_dict({"random_stream": "numpy", "drand48_seed": 5})
    assert (p.random_stream, p.drand48_seed) == ("numpy", 5)
    assert params_from_dict({"drand48_seed": 2 ** 32 - 1}).drand48_seed == 2 ** 32 - 1
    with pytest.raises(InputError, match="random_stream must be one of drand48, numpy"):
        params_from_dict({"random_stream": "pcg64"}, "x.yaml")
    with pytest.raises(InputError, match="'drand48_seed' must be in"):
        params_from_dict({"drand48_seed": -1}, "x.yaml")
    with pytest.raises(InputError, match="'drand48_seed' must be in"):
        params_from_dict({"drand48_seed": 2 ** 32}, "x.yaml")
    with pytest.raises(InputError, match="drand48_seed"):
        params_from_dict({"drand48_seed": 1.5}, "x.yaml")
    with pytest.raises(InputError, match="did you mean 'drand48_seed'"):
        params_from_dict({"drand48_sed": 1}, "x.yaml")


def test_records_without_a_stream_replay_on_numpy():
    """run.json files written before ``random_stream`` existed ran on the numpy stream."""
    old = {k: v for k, v in params_to_dict(GMappingParams()).items()
           if k not in ("random_stream", "drand48_seed")}
    assert params_from_record(old).random_stream == "numpy"
    assert params_from_record({**old, "random_stream": "drand48"}).random_stream == "drand48"
    assert params_from_record(params_to_dict(GMappingParams())) == GMappingParams()


def test_the_numpy_stream_keeps_the_hash_configs_had_before_the_option():
    """A campaign collected before ``random_stream`` existed can be resumed with
    ``random_stream: numpy`` (same config hash); the drand48 default is another config."""
    import hashlib
    import json

    from slam_predict.config import config_hash

    numpy = GMappingParams(particles=40, random_stream="numpy")
    old = {k: v for k, v in params_to_dict(numpy).items()
           if k not in ("random_stream", "drand48_seed")}
    before = hashlib.sha256(json.dumps(old, sort_keys=True).encode()).hexdigest()[:12]
    assert config_hash(numpy) == before
    assert config_hash(GMappingParams(particles=40)) != before
    assert config_hash(GMappingParams(particles=40, random_stream="numpy", drand48_seed=3)) \
        != before
