"""The report's configuration-hash table names the SLAM back-end the runs used."""
from __future__ import annotations

from pathlib import Path

from slam_predict.report.campaign import Run
from slam_predict.report.sections import hash_keys, hash_table


def run(world: str, hashes: dict) -> Run:
    return Run(world, "run_000", Path("."), {"config_hashes": hashes})


def test_columns_follow_the_hashes_the_runs_record():
    karto = run("a", {"sim": "s", "karto": "k1", "nav": "n", "explore": "e", "stop": "t",
                      "metric": "m"})
    assert hash_keys([karto]) == ["sim", "karto", "nav", "explore", "stop", "metric"]
    html = hash_table([karto])
    assert "<th>karto</th>" in html and "gmapping" not in html and "k1" in html
    gmapping = run("b", {"sim": "s", "gmapping": "g1", "slam_compute": "c", "nav": "n"})
    assert hash_keys([gmapping]) == ["sim", "gmapping", "slam_compute", "nav", "explore",
                                     "stop", "metric"]
    assert hash_keys([karto, gmapping])[:4] == ["sim", "gmapping", "karto", "slam_compute"]
    assert hash_keys([run("c", {})]) == ["sim", "gmapping", "nav", "explore", "stop", "metric"]
