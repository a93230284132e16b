"""``slam-predict worlds {show,convert,validate}``: outputs; bad input → one line, exit 2."""
from __future__ import annotations

import re
from pathlib import Path

import cv2
import numpy as np
import pytest

from slam_predict.cli.main import main
from slam_predict.world.load import load_plan


def plan_png(path: Path) -> Path:
    grey = np.zeros((30, 40), np.uint8)
    grey[2:-2, 2:-2] = 255
    grey[2:-2, 20] = 0
    grey[12:18, 20] = 255   # a door in the middle wall
    cv2.imwrite(str(path), grey)
    return path


def run(capsys, *argv):
    code = main(["worlds", *map(str, argv)])
    out, err = capsys.readouterr()
    return code, out, err


def test_validate_prints_one_summary_line(tmp_path, capsys):
    code, out, err = run(capsys, "validate", plan_png(tmp_path / "p.png"), "--resolution", 0.1)
    assert code == 0 and err == ""
    assert out.count("\n") == 1
    assert re.match(r"p: 40 x 30 px at 0\.1 m/px \(4\.00 x 3\.00 m\), free 9\.\d+ m², "
                    r"start \(-?\d+\.\d\d, -?\d+\.\d\d, 0\.0 deg\), 1 connected free component$",
                    out.strip())


def test_validate_counts_components_and_reports_start(tmp_path, capsys):
    grey = cv2.imread(str(plan_png(tmp_path / "p.png")), cv2.IMREAD_GRAYSCALE)
    grey[12:18, 20] = 0   # close the door: two rooms
    cv2.imwrite(str(tmp_path / "two.png"), grey)
    code, out, _ = run(capsys, "validate", tmp_path / "two.png", "--resolution", 0.1,
                       "--start", -1, 0.5, 45)
    assert code == 0
    assert "start (-1.00, 0.50, 45.0 deg), 2 connected free components" in out


def test_convert_writes_a_loadable_world(tmp_path, capsys):
    out_world = tmp_path / "out" / "p.world"
    code, out, _ = run(capsys, "convert", plan_png(tmp_path / "p.png"), "--resolution", 0.1,
                       "--out", out_world, "--start", 1, -0.5, 180)
    assert code == 0 and out.startswith(f"wrote {out_world}")
    assert out_world.exists() and out_world.with_suffix(".png").exists()
    world = load_plan(out_world)
    assert world.start_pose[:2] == pytest.approx([1.0, -0.5])
    src = load_plan(tmp_path / "p.png", resolution=0.1, start=(1, -0.5, 180))
    assert np.array_equal(world.occupied, src.occupied)


def test_convert_with_snap_start(tmp_path, capsys):
    out_world = tmp_path / "w" / "p.world"
    code, _, err = run(capsys, "convert", plan_png(tmp_path / "p.png"), "--resolution", 0.1,
                       "--out", out_world, "--start", 0.05, 1.2, "--snap-start")
    assert code == 0, err
    world = load_plan(out_world)
    assert world.is_free_at(world.start_pose[:2])


def test_show_renders_a_png(tmp_path, capsys):
    world = tmp_path / "w" / "p.world"
    assert run(capsys, "convert", plan_png(tmp_path / "p.png"), "--resolution", 0.1,
               "--out", world)[0] == 0
    picture = tmp_path / "pic" / "p_show.png"
    code, out, _ = run(capsys, "show", world, "--out", picture, "--dpi", 60)
    assert code == 0 and out.strip() == f"wrote {picture}"
    image = cv2.imread(str(picture))
    assert image is not None and image.shape[0] > 100 and image.shape[1] > 100
    # the start arrow is drawn in red somewhere
    b, g, r = image[..., 0].astype(int), image[..., 1].astype(int), image[..., 2].astype(int)
    assert ((r > 180) & (g < 100) & (b < 100)).any()
    assert not list(picture.parent.glob(".*tmp"))


def test_help_lists_actions(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["worlds", "--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    for action in ("show", "convert", "validate"):
        assert action in out


def test_no_action_is_an_error(capsys):
    code, _, err = run(capsys)
    assert code == 2 and "choose an action" in err


def bad_world(tmp_path: Path, text: str) -> Path:
    plan_png(tmp_path / "p.png")
    path = tmp_path / "bad.world"
    path.write_text(text)
    return path


CASES = {
    "missing file": (lambda t: ["validate", t / "none.png", "--resolution", 0.1],
                     r"none\.png: plan not found"),
    "corrupt image": (lambda t: ["validate", _write(t / "c.png", b"\x89PNG garbage"),
                                 "--resolution", 0.1], r"c\.png: cannot read image"),
    "no free space": (lambda t: ["validate", _img(t / "k.png", np.zeros((9, 9), np.uint8)),
                                 "--resolution", 0.1], r"k\.png: image has no free space"),
    "not enclosed": (lambda t: ["validate", _img(t / "o.png", np.full((9, 9), 255, np.uint8)),
                                "--resolution", 0.1], r"o\.png: no enclosed building"),
    "no scale": (lambda t: ["validate", plan_png(t / "p.png")], r"give --resolution"),
    "scale zero": (lambda t: ["validate", plan_png(t / "p.png"), "--resolution", 0],
                   r"--resolution must be > 0"),
    "start in wall": (lambda t: ["validate", plan_png(t / "p.png"), "--resolution", 0.1,
                                 "--start", 0.05, 1.45], r"inside a wall \(use --snap-start\)"),
    "start outside": (lambda t: ["validate", plan_png(t / "p.png"), "--resolution", 0.1,
                                 "--start", 30, 0], r"is outside the map"),
    "start arity": (lambda t: ["validate", plan_png(t / "p.png"), "--resolution", 0.1,
                               "--start", 1, 2, 3, 4], r"--start takes X Y \[YAW\]"),
    "syntax error": (lambda t: ["validate", bad_world(t, 'name "x"\nmodel( size [1 2 3] ) )\n')],
                     r"bad\.world:2: syntax error"),
    "unknown type": (lambda t: ["validate", bad_world(t, "\nflorplan( size [1 1 1] )\n")],
                     r"bad\.world:2: unknown model type 'florplan'"),
    "unknown property": (lambda t: ["validate", bad_world(
        t, 'model( bitmap "p.png" size [4 3 1]\n sise [1 1 1] )\n')],
        r"bad\.world:2: unknown property 'sise' in model \(model\) \(did you mean 'size'\?\)"),
    "missing bitmap": (lambda t: ["validate", bad_world(
        t, 'model( bitmap "gone.png" size [4 3 1] )\n')], r"bad\.world:1: bitmap 'gone\.png'"),
    "size missing": (lambda t: ["validate", bad_world(t, 'model( bitmap "p.png" )\n')],
                     r"has no 'size \[W H Z\]'"),
    "size negative": (lambda t: ["validate", bad_world(
        t, 'model( bitmap "p.png" size [4 -3 1] )\n')], r"size of model must be > 0"),
    "convert suffix": (lambda t: ["convert", plan_png(t / "p.png"), "--resolution", 0.1,
                                  "--out", t / "x.txt"], r"--out must name a \.world file"),
    "convert overwrites input": (lambda t: ["convert", plan_png(t / "p.png"), "--resolution",
                                            0.1, "--out", t / "p.world"],
                                 r"p\.png: the bitmap written beside --out file exists; use "
                                 r"--force"),
    "convert overwrites input, forced": (lambda t: ["convert", plan_png(t / "p.png"),
                                                    "--resolution", 0.1, "--out", t / "p.world",
                                                    "--force"],
                                         r"p\.png: the bitmap written beside --out would "
                                         r"overwrite this"),
    "show format": (lambda t: ["show", plan_png(t / "p.png"), "--resolution", 0.1,
                               "--out", t / "x.gif"], r"picture format '\.gif' not supported"),
}


def _write(path: Path, data: bytes) -> Path:
    path.write_bytes(data)
    return path


def _img(path: Path, grey: np.ndarray) -> Path:
    cv2.imwrite(str(path), grey)
    return path


@pytest.mark.parametrize("case", sorted(CASES))
def test_bad_input_is_one_line_exit_2(tmp_path, capsys, case):
    make_args, pattern = CASES[case]
    code, out, err = run(capsys, *make_args(tmp_path))
    assert code == 2
    assert err.count("\n") == 1 and err.startswith("slam-predict worlds: error: ")
    assert re.search(pattern, err), err
    assert "Traceback" not in err
    written = {p.name for p in tmp_path.rglob("*")} - {"bad.world", "p.png"}
    assert not {n for n in written if n.startswith(("x.", ".")) or n.endswith(".world")}


def test_generate_extension_module_is_registered(monkeypatch, capsys):
    import sys
    import types

    calls = []
    fake = types.ModuleType("slam_predict.cli.worlds_generate")

    def add_generate(sub):
        p = sub.add_parser("generate", help="fake generator")
        p.add_argument("--kind")
        p.set_defaults(worlds_run=lambda args: calls.append(args.kind) or 0)

    fake.add_generate = add_generate
    fake.add_import_thesis = lambda sub: sub.add_parser("import-thesis", help="fake import")
    monkeypatch.setitem(sys.modules, "slam_predict.cli.worlds_generate", fake)
    assert main(["worlds", "generate", "--kind", "office"]) == 0
    assert calls == ["office"]
    with pytest.raises(SystemExit):
        main(["worlds", "--help"])
    assert "import-thesis" in capsys.readouterr().out
