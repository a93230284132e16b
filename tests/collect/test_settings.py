"""collect settings: defaults, ``extends`` and ``sim_overrides`` (the fidelity variants)."""
from pathlib import Path

import pytest

from slam_predict.cli.main import main
from slam_predict.collect.settings import load_settings, read_settings_tree
from slam_predict.errors import InputError

CONFIG = Path(__file__).resolve().parents[2] / "config"


def test_default_settings_load_the_package_configs():
    settings = load_settings()
    assert settings.sim.odom.model == "uniform_per_run"
    assert settings.sim.laser.range_max == 80.0
    assert settings.slam.params.particles == 40


@pytest.mark.parametrize(("model", "laser_range"),
                         [("uniform_per_run", 60), ("fixed", 60), ("fixed", 80)])
def test_fidelity_variants_override_only_odometry_and_range(model, laser_range):
    base = load_settings()
    variant = load_settings(CONFIG / "fidelity" / f"{model}_{laser_range}.yaml")
    assert variant.sim.odom.model == model
    assert variant.sim.laser.range_max == float(laser_range)
    assert variant.sim.odom.error == base.sim.odom.error
    assert variant.sim.laser.samples == base.sim.laser.samples
    assert variant.hashes()["gmapping"] == base.hashes()["gmapping"]
    assert variant.hashes()["nav"] == base.hashes()["nav"]
    assert variant.stop == base.stop


def test_extends_resolves_paths_relative_to_each_file(tmp_path):
    (tmp_path / "child.yaml").write_text(
        f"extends: {CONFIG / 'collect.yaml'}\nstop:\n  mse_threshold: 5.0\n")
    tree = read_settings_tree(tmp_path / "child.yaml")
    assert Path(tree["robot"]) == CONFIG / "robot.yaml"
    settings = load_settings(tmp_path / "child.yaml")
    assert settings.stop.mse_threshold == 5.0
    assert settings.stop.interval_s == load_settings().stop.interval_s


def test_sim_overrides_choose_the_stage_ranger(tmp_path):
    (tmp_path / "stage.yaml").write_text(
        f"extends: {CONFIG / 'collect.yaml'}\nsim_overrides:\n  ranger_model: stage\n")
    base, stage = load_settings(), load_settings(tmp_path / "stage.yaml")
    assert base.sim.ranger_model == "exact" and stage.sim.ranger_model == "stage"
    assert stage.sim.integrator == base.sim.integrator
    assert stage.hashes()["sim"] != base.hashes()["sim"]
    assert stage.hashes()["gmapping"] == base.hashes()["gmapping"]


def test_unknown_override_key_is_a_one_line_error(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text(f"extends: {CONFIG / 'collect.yaml'}\n"
                   "sim_overrides:\n  laser:\n    rnage_max: 60\n")
    with pytest.raises(InputError, match="rnage_max"):
        load_settings(bad)
    world = Path(__file__).resolve().parents[2] / "worlds" / "tiny.world"
    code = main(["collect", str(world), "--runs", "1", "--out", str(tmp_path / "d"),
                 "--settings", str(bad), "--no-progress"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "rnage_max" in err[0]
    assert not (tmp_path / "d" / "tiny").exists()


def test_extends_loop_and_missing_parent_are_errors(tmp_path):
    (tmp_path / "a.yaml").write_text("extends: b.yaml\n")
    (tmp_path / "b.yaml").write_text("extends: a.yaml\n")
    with pytest.raises(InputError, match="loop"):
        load_settings(tmp_path / "a.yaml")
    (tmp_path / "c.yaml").write_text("extends: nowhere.yaml\n")
    with pytest.raises(InputError, match="missing file"):
        load_settings(tmp_path / "c.yaml")


def test_old_gmapping_key_is_read_with_a_deprecation_warning(tmp_path):
    (tmp_path / "old.yaml").write_text(f"extends: {CONFIG / 'collect.yaml'}\n"
                                       f"gmapping: {CONFIG / 'gmapping.yaml'}\n")
    with pytest.deprecated_call(match="'gmapping: FILE' is deprecated"):
        old = load_settings(tmp_path / "old.yaml")
    new = load_settings()
    assert old.slam.type == new.slam.type == "gmapping" and old.slam.params == new.slam.params
    assert old.hashes() == new.hashes()
    (tmp_path / "both.yaml").write_text("gmapping: gmapping.yaml\nslam: {type: gmapping}\n")
    with pytest.raises(InputError, match="both 'slam' and the deprecated 'gmapping'"):
        load_settings(tmp_path / "both.yaml")


def test_slam_section_takes_a_file_inline_parameters_or_defaults(tmp_path):
    (tmp_path / "inline.yaml").write_text(f"extends: {CONFIG / 'collect.yaml'}\n"
                                          "slam: {params: {particles: 7}}\n")
    assert load_settings(tmp_path / "inline.yaml").slam.params.particles == 7
    (tmp_path / "defaults.yaml").write_text(f"extends: {CONFIG / 'collect.yaml'}\n"
                                            "slam: {type: gmapping}\n")
    settings = load_settings(tmp_path / "defaults.yaml")
    assert settings.slam.params.particles == 30   # slam_gmapping's default, not the thesis' 40
    assert settings.hashes()["gmapping"] == settings.slam.params_hash()
    assert settings.slam.record() == {"type": "gmapping",
                                      "params_hash": settings.slam.params_hash()}
    (tmp_path / "bad.yaml").write_text(f"extends: {CONFIG / 'collect.yaml'}\n"
                                       "slam: {type: gmapping, params: [1, 2]}\n")
    with pytest.raises(InputError, match="slam.params must be"):
        load_settings(tmp_path / "bad.yaml")


def test_fitted_settings_are_declared_checked_and_change_no_hash(tmp_path):
    """config/fidelity/seed_study.yaml declares its fitted rebuild cost; extending files inherit
    it, null drops it, a key naming no setting is an error, and no run hash changes."""
    fidelity = load_settings(CONFIG / "fidelity" / "seed_study.yaml")
    assert list(fidelity.fitted) == ["slam_compute.rebuild_s_per_line_cell"]
    assert list(load_settings(CONFIG / "robot_campaign" / "settings.yaml").fitted) == \
        ["slam_compute.rebuild_s_per_line_cell"]
    assert load_settings(CONFIG / "fidelity" / "seed_study_karto.yaml").fitted == {}
    assert load_settings().fitted == {}
    same = tmp_path / "same.yaml"
    same.write_text(f"extends: {CONFIG / 'fidelity' / 'seed_study.yaml'}\nfitted: {{}}\n")
    assert load_settings(same).hashes() == fidelity.hashes()
    for key in ("slam_compute.no_such_key", "nosuch.section", "slam_compute", "robot.range",
                "sensor_logs.x", "fitted.x"):
        bad = tmp_path / "bad.yaml"
        bad.write_text(f"extends: {CONFIG / 'collect.yaml'}\nfitted:\n  {key}: chosen by eye\n")
        with pytest.raises(InputError, match="names no setting"):
            load_settings(bad)


def test_nav_overrides_set_move_base_keys_and_only_the_nav_hash_changes():
    """seed_study_back_up.yaml: seed_study.yaml with the oscillation trigger and a back-up."""
    base = load_settings(CONFIG / "fidelity" / "seed_study.yaml")
    mended = load_settings(CONFIG / "fidelity" / "seed_study_back_up.yaml")
    assert mended.nav.oscillation_timeout == 60.0 and base.nav.oscillation_timeout == 0.0
    assert mended.nav.oscillation_across_goals and not base.nav.oscillation_across_goals
    (back_up,) = mended.nav.oscillation_recovery_behaviors
    assert (back_up.type, back_up.backup_dist, back_up.backup_speed) == (
        "slam_predict/BackUpRecovery", 0.5, 0.15)
    assert mended.nav.recovery_behaviors == base.nav.recovery_behaviors
    differ = {k for k, v in mended.hashes().items() if base.hashes()[k] != v}
    assert differ == {"nav"}
    assert mended.fitted == base.fitted


def test_the_ros_path_gets_the_overridden_navigation_folder():
    """The move_base node loads the folder component_configs names: the same config."""
    from slam_predict.nav.config import load_nav_config
    from slam_predict.ros.batch_runner import component_configs

    path = CONFIG / "fidelity" / "seed_study_back_up.yaml"
    folder = component_configs(path)["nav_config_dir"]
    assert load_nav_config(folder) == load_settings(path).nav
    plain = component_configs(CONFIG / "fidelity" / "seed_study.yaml")["nav_config_dir"]
    assert Path(plain) == CONFIG.resolve()


@pytest.mark.parametrize("key", ["global_costmap", "oscilation_timeout"])
def test_nav_overrides_of_a_section_or_an_unknown_key_are_one_line_errors(tmp_path, key):
    settings = tmp_path / "s.yaml"
    settings.write_text(f"extends: {CONFIG / 'collect.yaml'}\nnav_overrides:\n  {key}: 1.0\n")
    with pytest.raises(InputError, match=f"nav_overrides: '{key}'"):
        load_settings(settings)


@pytest.mark.parametrize("value", ["1.0", "{escape_alternat: true}"])
def test_trajectory_planner_overrides_name_known_parameters(tmp_path, value):
    settings = tmp_path / "s.yaml"
    settings.write_text(f"extends: {CONFIG / 'collect.yaml'}\nnav_overrides:\n"
                        f"  TrajectoryPlannerROS: {value}\n")
    with pytest.raises(InputError, match="nav_overrides.TrajectoryPlannerROS: not a") as err:
        load_settings(settings)
    assert str(settings) in str(err.value) and "\n" not in str(err.value)


def test_trajectory_planner_overrides_reach_both_paths_and_only_the_nav_hash(tmp_path):
    """A TrajectoryPlannerROS key set in nav_overrides (one the planner file also sets, and one
    it does not) reaches the in-process settings and the ROS path's navigation folder."""
    from slam_predict.nav.config import load_nav_config
    from slam_predict.ros.batch_runner import component_configs

    path = tmp_path / "s.yaml"
    path.write_text(f"extends: {CONFIG / 'collect.yaml'}\nnav_overrides:\n"
                    "  TrajectoryPlannerROS: {escape_alternate: true, escape_vel: -0.2}\n")
    base, settings = load_settings(CONFIG / "collect.yaml"), load_settings(path)
    tp = settings.nav.TrajectoryPlannerROS
    assert tp.escape_alternate and tp.escape_vel == -0.2
    assert not base.nav.TrajectoryPlannerROS.escape_alternate
    assert settings.nav.TrajectoryPlannerROS.max_vel_x == base.nav.TrajectoryPlannerROS.max_vel_x
    assert {k for k, v in settings.hashes().items() if base.hashes()[k] != v} == {"nav"}
    folder = component_configs(path)["nav_config_dir"]
    assert load_nav_config(folder) == settings.nav


def test_two_jobs_making_the_same_navigation_folder_both_get_it(tmp_path, monkeypatch):
    """Parallel collect jobs on the ROS path: a job that finds the folder made by another
    between its check and its rename keeps that folder and drops its own staging copy."""
    from slam_predict.collect import settings_files
    from slam_predict.collect.settings import read_settings_tree

    monkeypatch.setattr(Path, "home", lambda: tmp_path)
    tree = read_settings_tree(CONFIG / "fidelity" / "seed_study_back_up.yaml")
    first = settings_files.merged_nav_folder(tree)
    real_is_dir = Path.is_dir
    calls = []

    def not_yet(path):   # the second job's first look: the folder is not there yet
        if path == first and not calls:
            calls.append(path)
            return False
        return real_is_dir(path)

    monkeypatch.setattr(Path, "is_dir", not_yet)
    assert settings_files.merged_nav_folder(tree) == first and calls
    assert sorted(p.name for p in first.parent.iterdir() if p.is_dir()) == [first.name]


def test_explore_overrides_reach_both_paths_and_only_the_explore_hash(tmp_path, monkeypatch):
    """seed_study_reachable.yaml sets reachable_frontiers over config/explore.yaml: the
    in-process settings and the ROS path's explore file get it; only the explore hash moves,
    and the older chain's explore hash is the one its records state."""
    from slam_predict.config import load_config
    from slam_predict.explore.explorer import ExploreConfig
    from slam_predict.ros.batch_runner import component_configs

    monkeypatch.setattr(Path, "home", lambda: tmp_path)
    base = load_settings(CONFIG / "fidelity" / "seed_study_refit_escape.yaml")
    path = CONFIG / "fidelity" / "seed_study_reachable.yaml"
    settings = load_settings(path)
    assert settings.explore.reachable_frontiers and not base.explore.reachable_frontiers
    assert {k for k, v in settings.hashes().items() if base.hashes()[k] != v} == {"explore"}
    assert base.hashes()["explore"] == load_settings(CONFIG / "collect.yaml").hashes()["explore"]
    explore_file = component_configs(path)["explore_config"]
    assert load_config(ExploreConfig, explore_file) == settings.explore
    plain = component_configs(CONFIG / "fidelity" / "seed_study_refit_escape.yaml")
    assert Path(plain["explore_config"]) == (CONFIG / "explore.yaml").resolve()


def test_an_unknown_explore_override_is_a_one_line_error(tmp_path):
    settings = tmp_path / "s.yaml"
    settings.write_text(f"extends: {CONFIG / 'collect.yaml'}\nexplore_overrides:\n"
                        "  reachable_frontier: true\n")
    with pytest.raises(InputError, match="reachable_frontier") as err:
        load_settings(settings)
    assert "\n" not in str(err.value)


def test_local_costmap_overrides_reach_both_paths(tmp_path):
    """A local_costmap key in nav_overrides sets the in-process costmap and the merged folder's
    local_costmap.yaml alike; the rest of the section keeps its file's values."""
    from slam_predict.nav.config import load_nav_config
    from slam_predict.ros.batch_runner import component_configs

    path = tmp_path / "s.yaml"
    path.write_text(f"extends: {CONFIG / 'collect.yaml'}\nnav_overrides:\n"
                    "  local_costmap: {footprint_clearing_enabled: true}\n")
    settings, base = load_settings(path), load_settings(CONFIG / "collect.yaml")
    assert settings.nav.local_costmap.footprint_clearing_enabled
    assert not base.nav.local_costmap.footprint_clearing_enabled
    assert settings.nav.local_costmap.resolution == base.nav.local_costmap.resolution
    folder = component_configs(path)["nav_config_dir"]
    assert load_nav_config(folder) == settings.nav
    with pytest.raises(InputError, match="nav_overrides.local_costmap: not a"):
        path.write_text(f"extends: {CONFIG / 'collect.yaml'}\nnav_overrides:\n"
                        "  local_costmap: {footprint_clearing: true}\n")
        load_settings(path)



def test_the_cleared_footprint_chain_is_the_refit_escape_chain_plus_two_rules(tmp_path):
    """seed_study_clear_footprint.yaml (through seed_study_clear_refit.yaml, which repeats
    seed_study_refit_escape.yaml's sections to stay shallow) resolves to what extending that file
    with its two navigation rules gives, and so do its record hashes (fidelity_seed_study_8's)."""
    extended = tmp_path / "extended.yaml"
    extended.write_text(
        f"extends: {CONFIG / 'fidelity' / 'seed_study_refit_escape.yaml'}\n"
        "nav_overrides:\n  TrajectoryPlannerROS:\n    upstream_rules: true\n"
        "  local_costmap:\n    footprint_clearing_enabled: true\n")
    repeated = load_settings(CONFIG / "fidelity" / "seed_study_clear_footprint.yaml")
    reference = load_settings(extended)
    assert repeated.hashes() == reference.hashes()
    assert repeated.fitted == reference.fitted
    for part in ("sim", "nav", "explore", "stop", "metric", "compute"):
        assert getattr(repeated, part) == getattr(reference, part), part
    assert repeated.nav.TrajectoryPlannerROS.upstream_rules
    assert repeated.nav.local_costmap.footprint_clearing_enabled


def test_the_refitted_chain_differs_from_the_cleared_footprint_chain_in_compute_only():
    """seed_study_clear_refit.yaml (fidelity_seed_study_9) is fidelity_seed_study_8's chain with
    GMapping's compute level refitted: every other part, and so the route a Karto replay checks
    (`slam beside`), hashes alike; the fitted text names the new value."""
    refit = load_settings(CONFIG / "fidelity" / "seed_study_clear_refit.yaml")
    cleared = load_settings(CONFIG / "fidelity" / "seed_study_clear_footprint.yaml")
    assert refit.compute.cpu_factor == 1.0 and cleared.compute.cpu_factor == 0.88
    new, old = refit.hashes(), cleared.hashes()
    assert {k for k in new if new[k] != old[k]} == {"slam_compute"}
    assert refit.fitted["slam_compute.cpu_factor"].startswith("1.0, chosen")
    assert cleared.fitted["slam_compute.cpu_factor"].startswith("0.88, chosen")
