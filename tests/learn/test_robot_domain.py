"""GMapping's maxUrange of the runs (the range input's cap) and the design's bounds."""
from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.learn.robot.domain import (
    MaxUrangeSource,
    common_max_urange,
    design_ranges,
    settings_cap,
)
from slam_predict.learn.robot.inputs import ROBOT_INPUTS
from slam_predict.slam.gmapping.params import GMappingParams

from . import robot_synthetic as syn


def test_settings_cap_is_maxurange_then_maxrange_then_none():
    params = GMappingParams(maxRange=60.0, maxUrange=30.0)
    assert settings_cap(params) == 30.0
    assert settings_cap(dataclasses.replace(params, maxUrange=None)) == 60.0
    assert settings_cap(dataclasses.replace(params, maxUrange=None, maxRange=None)) is None


def test_runs_get_the_maxurange_of_their_settings_file(tmp_path):
    """The synthetic runs name config/collect.yaml (maxUrange 30 m) with the hash of its
    GMapping parameters capped for their laser; an 80 m laser becomes a 30 m input."""
    rng = np.random.default_rng(2)
    robots = syn.robot_configs(2, rng)
    robots[1]["range_max"] = 80.0
    worlds = syn.buildings(2, rng)
    records = syn.write_campaign(tmp_path, worlds, robots, 1, rng)
    source = MaxUrangeSource()
    assert [source.of_record(r, r["path"]) for r in records] == [30.0] * 4
    assert MaxUrangeSource(25.0).of_record({}, "x") == 25.0      # robot_learning.max_urange_m
    data = syn.load(tmp_path, worlds)
    assert data.max_urange_m == 30.0
    assert {r.robot["laser_range_max_m"] for r in data.runs if r.config == "c01"} == {30.0}


def test_a_run_collected_without_robot_file_has_uncapped_parameters(tmp_path):
    """collect without --robot records the settings' own parameters (no per-laser cap)."""
    from slam_predict.config import config_hash

    record = syn.record("w00", 0, 1, {"range_max": 20.0, "fov": 270.0, "xy": 0.01,
                                      "yaw": syn.YAW}, (0.1, 0.01), None)
    record["config_hashes"]["gmapping"] = config_hash(syn._gmapping_params())
    assert MaxUrangeSource().of_record(record, "run.json") == 30.0


def test_runs_of_two_maxurange_values_are_refused():
    assert common_max_urange({"a": 30.0, "b": 30.0}) == 30.0 and common_max_urange({}) is None
    with pytest.raises(InputError, match="different GMapping maxUrange: unset .* here, "
                                         "30 m in a") as err:
        common_max_urange({"a": 30.0, "b": None})
    assert err.value.one_line().startswith("b: ")


def test_changed_settings_need_max_urange_m(tmp_path):
    settings = tmp_path / "settings.yaml"
    settings.write_text(f"extends: {syn.ROOT / 'config' / 'collect.yaml'}\n")
    record = syn.record("w00", 0, 1, {"range_max": 10.0, "fov": 270.0, "xy": 0.01,
                                      "yaw": syn.YAW}, (0.1, 0.01), None)
    record["settings_file"] = str(settings)          # absolute: taken as it is
    assert MaxUrangeSource().of_record(record, "run.json") == 30.0
    record["config_hashes"]["gmapping"] = "000000000000"
    with pytest.raises(InputError, match="set robot_learning.max_urange_m"):
        MaxUrangeSource().of_record(record, "run.json")
    assert MaxUrangeSource(30.0).of_record(record, "run.json") == 30.0


def test_a_run_whose_settings_file_is_gone_takes_its_campaigns(tmp_path):
    """A run naming a settings file removed since falls back to the campaign.json beside its
    world folder (the hash check still applies); without one it is the one-line error."""
    import json

    record = syn.record("w00", 0, 1, {"range_max": 10.0, "fov": 270.0, "xy": 0.01,
                                      "yaw": syn.YAW}, (0.1, 0.01), None)
    record["settings_file"] = "config/fidelity/probes/removed.yaml"
    run = tmp_path / "camp" / "w00" / "run_000" / "run.json"
    run.parent.mkdir(parents=True)
    with pytest.raises(InputError, match="removed.yaml of the run not found"):
        MaxUrangeSource().of_record(record, run)
    (tmp_path / "camp" / "campaign.json").write_text(
        json.dumps({"settings_file": "config/collect.yaml"}))
    assert MaxUrangeSource().of_record(record, run) == 30.0
    record["config_hashes"]["gmapping"] = "000000000000"
    with pytest.raises(InputError, match="set robot_learning.max_urange_m"):
        MaxUrangeSource().of_record(record, run)


@pytest.fixture(scope="module")
def designed(tmp_path_factory):
    folder = tmp_path_factory.mktemp("designed")
    worlds, robots, _ = syn.campaign(folder / "data", n_worlds=3, n_configs=4)
    return syn.write_design(folder / "design.yaml", worlds, robots), syn.load(folder / "data",
                                                                               worlds)


def test_design_ranges_are_its_bounds_in_input_units(designed):
    design, data = designed
    ranges = design_ranges(design, 30.0, data.configs)
    assert list(ranges) == [*ROBOT_INPUTS, "laser_resolution_deg"]
    assert ranges["laser_resolution_deg"] == [0.5, 0.5]
    assert ranges["laser_range_max_m"] == [3.5, 30.0]
    assert ranges["laser_fov_deg"] == pytest.approx([180.0, 360.0])
    assert ranges["odom_xy_error"] == pytest.approx([0.0, 0.02])
    assert ranges["odom_yaw_error"] == pytest.approx([0.0, 2 * syn.YAW])
    assert design_ranges(design, 10.0, {})["laser_range_max_m"] == [3.5, 10.0]


def test_a_design_that_does_not_match_the_runs_is_refused(designed, tmp_path):
    design, data = designed
    configs = dict(data.configs)
    with pytest.raises(InputError, match="configuration 'c09' of the runs is not in the design"):
        design_ranges(design, 30.0, {**configs, "c09": configs["c00"]})
    other = json.loads(json.dumps(configs))
    other["c01"]["laser_fov_deg"] += 10.0
    with pytest.raises(InputError, match="configuration 'c01': laser_fov_deg is .* in the "
                                         "design, .* in the runs") as err:
        design_ranges(design, 30.0, other)
    assert err.value.one_line().startswith(str(design))


def test_several_design_files_pool_their_configurations(designed, tmp_path):
    """A campaign's design and an extension that adds configurations: the runs' configurations
    may come from either; the files must agree on bounds, base robot and on any id they share."""
    import yaml

    design, data = designed
    content = yaml.safe_load(open(design))
    configs = content["configs"]
    first = dict(content, configs={k: configs[k] for k in ("c00", "c01")},
                 worlds={w: ["c00", "c01"] for w in content["worlds"]})
    second = dict(content, configs={k: configs[k] for k in ("c02", "c03")},
                  worlds={w: ["c02", "c03"] for w in content["worlds"]})
    a, b = tmp_path / "a.yaml", tmp_path / "b.yaml"
    a.write_text(yaml.safe_dump(first))
    b.write_text(yaml.safe_dump(second))
    assert design_ranges([a, b], 30.0, data.configs) == design_ranges(design, 30.0, data.configs)
    with pytest.raises(InputError, match="configuration 'c02' of the runs is not in the design"):
        design_ranges([a], 30.0, data.configs)
    clash = dict(second, configs={"c00": configs["c02"], "c03": configs["c03"]},
                 worlds={w: ["c00", "c03"] for w in content["worlds"]})
    b.write_text(yaml.safe_dump(clash))
    with pytest.raises(InputError, match="configuration 'c00' differs from .*a.yaml's"):
        design_ranges([a, b], 30.0, data.configs)
    wider = dict(second, bounds=dict(content["bounds"], fov=[90.0, 360.0]))
    b.write_text(yaml.safe_dump(wider))
    with pytest.raises(InputError, match="bounds or base robot differ"):
        design_ranges([a, b], 30.0, data.configs)


def test_design_files_of_other_resolutions_pool_only_when_the_model_learns_it(designed,
                                                                            tmp_path):
    """The same box at another angular resolution (0.25° and 1° beside 0.5°): refused for a
    model without the resolution input, with the option that accepts it; accepted with it,
    the resolution's range then being the files'."""
    import yaml

    design, data = designed
    content = yaml.safe_load(open(design))
    fine = dict(content, resolution_deg=0.25, configs={"f00": content["configs"]["c00"]},
                worlds={w: ["f00"] for w in content["worlds"]})
    path = tmp_path / "fine.yaml"
    path.write_text(yaml.safe_dump(fine))
    with pytest.raises(InputError, match=r"angular resolution \(0.25 deg\) differs .*"
                                         "resolution_input: true"):
        design_ranges([design, path], 30.0, data.configs)
    ranges = design_ranges([design, path], 30.0, data.configs, resolution_input=True)
    assert ranges["laser_resolution_deg"] == [0.25, 0.5]
    assert {k: v for k, v in ranges.items() if k != "laser_resolution_deg"} == \
        {k: v for k, v in design_ranges(design, 30.0, data.configs).items()
         if k != "laser_resolution_deg"}
    wrong = json.loads(json.dumps(dict(data.configs)))
    wrong["c00"]["laser_resolution_deg"] = 1.0
    with pytest.raises(InputError, match="'c00': laser_resolution_deg is 0.5 in the design, "
                                         "1 in the runs"):
        design_ranges(design, 30.0, wrong)


def test_karto_runs_get_the_max_laser_range_of_their_settings_file():
    """A Karto run's range cap is its settings' max_laser_range (slam_toolbox: 20 m), checked
    against the run's recorded Karto config hash."""
    from slam_predict.collect.settings import load_settings
    from slam_predict.config import config_hash

    settings_file = "config/fidelity/seed_study_karto.yaml"
    params = load_settings(syn.ROOT / settings_file).slam.params
    record = syn.record("w00", 0, 1, {"range_max": 80.0, "fov": 270.0, "xy": 0.01,
                                      "yaw": syn.YAW}, (0.1, 0.01), None)
    record.update(settings_file=settings_file,
                  slam={"type": "karto", "params_hash": config_hash(params)},
                  config_hashes={"karto": config_hash(params), "sim": "s1"})
    assert MaxUrangeSource().of_record(record, "run.json") == params.max_laser_range == 20.0
    record["config_hashes"]["karto"] = "000000000000"
    with pytest.raises(InputError, match="Karto config .* the run recorded 000000000000"):
        MaxUrangeSource().of_record(record, "run.json")
    record["slam"]["type"] = record["config_hashes"]["cartographer"] = "cartographer"
    with pytest.raises(InputError, match="learn GMapping and Karto runs"):
        MaxUrangeSource().of_record(record, "run.json")


def test_runs_collected_without_the_design_join_inside_its_bounds(designed):
    """A configuration of runs with no design entry (e.g. the seed robot of the fidelity
    campaign) need not be in the file, but must lie inside its bounds."""
    design, data = designed
    configs = dict(data.configs)
    inside = dict(configs["c00"], laser_range_max_m=30.0, laser_fov_deg=270.0)
    ranges = design_ranges(design, 30.0, {**configs, "f61b30949018": inside},
                           undesigned={"f61b30949018"})
    assert ranges == design_ranges(design, 30.0, configs)
    wide = dict(inside, laser_fov_deg=90.0)
    with pytest.raises(InputError, match="'f61b30949018' .*laser_fov_deg 90 lies outside the "
                                         r"design's bounds \[180, 360\]"):
        design_ranges(design, 30.0, {**configs, "f61b30949018": wide},
                      undesigned={"f61b30949018"})
    with pytest.raises(InputError, match="'f61b30949018' of the runs is not in the design"):
        design_ranges(design, 30.0, {**configs, "f61b30949018": inside})
