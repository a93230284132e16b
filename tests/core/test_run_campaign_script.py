"""tools/run_campaign.sh refuses a bad ``--part`` with one line and exit code 2, before any work."""
import subprocess
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "tools" / "run_campaign.sh"


@pytest.mark.parametrize("args, message", [
    (["fidelity_seed_study_2", "--part", "half"], "--part must be fit or judge, got 'half'"),
    (["robots", "--part", "fit"], "--part only applies to the campaigns with parts.yaml"),
])
def test_bad_part_is_one_line_and_exit_2(args, message):
    proc = subprocess.run(["bash", str(SCRIPT), *args], capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert proc.stderr.strip().splitlines() == [f"run_campaign: {message}"]


def test_judged_runs_wait_for_the_whole_fit_part(tmp_path):
    """fidelity_seed_study_2 refuses judged runs (and a run of both parts) until every fit
    building has its runs; then it goes on to the next check (here: no shared data)."""
    (tmp_path / "tools").mkdir()
    script = tmp_path / "tools" / "run_campaign.sh"
    script.write_text(SCRIPT.read_text())
    campaigns = tmp_path / "data" / "campaigns"
    (campaigns / "fidelity_seed_study").mkdir(parents=True)
    (campaigns / "fidelity_seed_study" / "parts.yaml").write_text(
        "parts:\n  fit:\n    - A\n    - B\n  judge:\n    - C\n")
    for building, runs in (("A", 3), ("B", 2), ("C", 1)):
        for k in range(runs):
            run = campaigns / "fidelity_seed_study_2" / building / f"run_{k:03d}"
            run.mkdir(parents=True)
            (run / "run.json").write_text("{}")
    env = {"PATH": "/usr/bin:/bin", "SLAM_PREDICT_DATA": str(tmp_path / "no-data")}

    def run(*args):
        proc = subprocess.run(["bash", str(script), "fidelity_seed_study_2", *args],
                              capture_output=True, text=True, timeout=60, env=env)
        return proc.returncode, proc.stderr.strip()

    refusal = ("run_campaign: fidelity_seed_study_2: the fit part has 5 of its 6 runs; "
               "collect it first (--part fit)")
    assert run("--part", "judge") == (2, refusal)
    assert run() == (2, refusal)
    assert run("--part", "fit")[1].endswith("environments.csv not found (set SLAM_PREDICT_DATA)")
    (campaigns / "fidelity_seed_study_2" / "B" / "run_002").mkdir()
    (campaigns / "fidelity_seed_study_2" / "B" / "run_002" / "run.json").write_text("{}")
    assert run("--part", "judge")[1].endswith("not found (set SLAM_PREDICT_DATA)")


@pytest.mark.parametrize("name, settings, design", [
    ("robots_2", "config/robot_campaign/settings_refit_escape.yaml",
     "--design data/campaigns/robots/design.yaml"),
    ("robots_2_rep4", "config/robot_campaign/settings_refit_escape.yaml",
     "--design data/campaigns/robots/design.yaml --runs 4 --seed 4"),
    ("robots_2_res100", "config/robot_campaign/settings_refit_escape.yaml",
     "--design data/campaigns/robots/design_res100.yaml"),
    ("robots_rep4", "config/robot_campaign/settings.yaml",
     "--design data/campaigns/robots/design.yaml --runs 4 --seed 4"),
    ("karto_robots_2", "config/fidelity/seed_study_refit_escape_karto.yaml",
     "--design data/campaigns/robots/design.yaml --runs 4"),
    ("karto_seed_study_2", "config/fidelity/seed_study_refit_escape_karto.yaml", None),
])
def test_dry_run_names_the_settings_and_design(name, settings, design):
    """A *_2 campaign is its first collection's design on fidelity_seed_study_6's chain."""
    proc = subprocess.run(["bash", str(SCRIPT), name, "--dry-run"], capture_output=True,
                          text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    lines = dict(line.split(": ", 1) for line in proc.stdout.strip().splitlines())
    assert lines["campaign"] == name
    assert lines["settings"] == settings
    assert lines.get("design") == design
    assert (SCRIPT.parents[1] / settings).is_file()
    count = 17 + 27 if name.startswith("karto_seed_study") else 21
    assert lines[f"buildings ({count})"].count(" ") == count - 1
