"""`slam-predict collect --robot FILE`: a short run of the tiny world records the robot's sensor,
its GMapping range caps and config hashes of its own."""
import json

from robot_runs import LDS, TINY, short_settings

from slam_predict.cli.main import main
from slam_predict.collect.settings import load_settings


def test_collect_with_the_lds_robot_records_its_sensor(tmp_path, capsys):
    settings = short_settings(tmp_path)
    out = tmp_path / "data"
    code = main(["collect", str(TINY), "--runs", "1", "--out", str(out), "--settings",
                 str(settings), "--robot", str(LDS), "--no-progress"])
    assert code == 0, capsys.readouterr().err
    record = json.loads((out / "tiny" / "run_000" / "run.json").read_text())
    laser = record["sensor"]["laser"]
    assert laser["fov"] == 2 * 3.141592653589793 and laser["samples"] == 360
    assert laser["range_max"] == 3.5 and laser["range_min"] == 0.12 and laser["rate_hz"] == 5.0
    assert record["sim_duration_s"] > 20.0 and record["distance_m"] > 0.0
    plain = load_settings(settings).hashes()
    robot = load_settings(settings, robot=LDS).hashes()
    assert record["config_hashes"] == robot
    assert [k for k in plain if plain[k] != robot[k]] == ["sim", "gmapping"]
    campaign = json.loads((out / "campaign.json").read_text())
    assert campaign["settings"]["gmapping"]["maxRange"] == 60.0
    assert campaign["settings"]["gmapping"]["maxUrange"] == 3.49
    # resuming without --robot is another configuration: refused
    assert main(["collect", str(TINY), "--runs", "1", "--out", str(out), "--settings",
                 str(settings), "--no-progress"]) == 2
    assert "sim" in capsys.readouterr().err
