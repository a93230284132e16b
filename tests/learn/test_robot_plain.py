"""Plain-array forms of the robot-aware models: equal to the fitted scikit-learn pipelines
(to 1e-9) on random inputs, read back from JSON, and predicting without scikit-learn."""
from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from slam_predict.learn.robot.models import fit_component
from slam_predict.learn.robot.plain import (
    PlainComponentModel,
    matches,
    plain_component,
    plain_pipeline,
)

from . import robot_synthetic as syn

GP = "gaussian_process"


@pytest.fixture(scope="module")
def tables(tmp_path_factory):
    folder = tmp_path_factory.mktemp("plain")
    worlds, _, _ = syn.campaign(folder / "data", n_worlds=6, n_configs=3)
    return syn.load(folder / "data", worlds).tables(syn.FAST_FEATURES)


def random_rows(tables, n: int = 200, seed: int = 7) -> np.ndarray:
    """Rows drawn uniformly from half the training minimum to 1.5 × the maximum."""
    rng = np.random.default_rng(seed)
    low, high = tables.point_X.min(axis=0), tables.point_X.max(axis=0)
    return rng.uniform(0.5 * low, 1.5 * high, size=(n, tables.point_X.shape[1]))


CASES = [("elasticnet", "trans_mean", {}), ("gradient_boosting", "rot_mean", {}),
         ("trend_boosting", "trans_mean", {}),
         (GP, "trans_mean", {}), (GP, "trans_std", {"nu": 0.5}), (GP, "rot_mean", {"nu": 1.5}),
         (GP, "rot_std", {"nu": math.inf}), (GP, "trans_mean", {"nu": 1.0})]


@pytest.mark.parametrize("kind, component, gp", CASES,
                         ids=[f"{k}-{c}-{g.get('nu', 'default')}" for k, c, g in CASES])
def test_plain_form_equals_the_fitted_model(tables, kind, component, gp):
    config = syn.fast_config(conformal_folds=2, gaussian_process=gp)
    model = fit_component(tables, component, kind, config)
    form = plain_component(model, tables.point_X)
    assert form is not None
    plain = PlainComponentModel.from_form(json.loads(json.dumps(form)))
    X = random_rows(tables)
    np.testing.assert_allclose(plain.predict_log(X), model.predict_log(X), rtol=1e-9,
                               atol=1e-9)
    np.testing.assert_allclose(plain.predict(X), model.predict(X), rtol=1e-9)
    runs = 3 if "std" in component else 2
    np.testing.assert_allclose(plain.interval(X, 0.8, runs), model.interval(X, 0.8, runs),
                               rtol=1e-9)
    assert (plain.component, plain.kind, plain.names) == (component, kind, model.names)


def test_models_without_a_plain_form_or_not_matching_it_are_not_converted(tables):
    from sklearn.neighbors import KNeighborsRegressor
    from sklearn.pipeline import Pipeline

    model = fit_component(tables, "trans_mean", "elasticnet", syn.fast_config(conformal_folds=2))
    rng = np.random.default_rng(0)
    form = plain_pipeline(model.estimator, tables.point_X, rng)
    wrong = json.loads(json.dumps(form))
    wrong["model"]["intercept"] += 1e-6
    assert matches(form, model.estimator, tables.point_X)
    assert not matches(wrong, model.estimator, tables.point_X)
    log = model.estimator.named_steps["log"]
    knn = KNeighborsRegressor(3).fit(log.transform(tables.point_X), tables.point_X[:, 0])
    model.estimator = Pipeline([("log", log), ("model", knn)])
    assert plain_pipeline(model.estimator, tables.point_X, rng) is None
    assert plain_component(model, tables.point_X) is None


def test_predict_imports_neither_scikit_learn_nor_joblib(robot_models_dir, root):
    """The session's own-robots folder: every best model has a plain form, so loading and
    predicting stays numpy-only (importing scikit-learn costs 1.5 s of predict's 3)."""
    code = f"""
import sys
from slam_predict.learn.robot.predict import RobotModel
from slam_predict.learn.robot.plain import PlainComponentModel
model = RobotModel.load({str(robot_models_dir / 'own-robots')!r})
from slam_predict.features.sightline import CURVE_RANGES_M, curve_columns
plan = {{"building_area": 800.0, "building_perimeter": 130.0,
        "voronoi_traversal_distance": 320.0, "voronoi_traversal_rotation": 40.0}}
plan.update({{c: 0.5 ** r for c, r in zip(curve_columns(), CURVE_RANGES_M)}})
robot = {{"laser_range_max_m": 12.0, "laser_fov_deg": 270.0, "odom_xy_error": 0.01,
         "odom_yaw_error": 0.035, "laser_resolution_deg": 0.5}}
result = model.predict(plan, robot)
model.partial_dependence("trans_mean", "laser_range_max_m", 5)
assert all(isinstance(m, PlainComponentModel) for m in model.models.values())
assert all(result[c]["low"] <= result[c]["value"] <= result[c]["high"] for c in model.models)
print(sorted(m for m in sys.modules if m.split(".")[0] in ("sklearn", "joblib")))
"""
    proc = subprocess.run([sys.executable, "-c", code], cwd=root, capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[]"


def test_trend_boosting_plain_form_predicts_without_scikit_learn(tables, tmp_path, root):
    """The shipped mean ε_t model is trend boosting: its plain form, tail included, must
    evaluate with numpy alone, like the other kinds."""
    model = fit_component(tables, "trans_mean", "trend_boosting",
                          syn.fast_config(conformal_folds=2))
    form = plain_component(model, tables.point_X)
    assert form is not None and form["estimator"]["model"]["tail"]["columns"]
    (tmp_path / "form.json").write_text(json.dumps(form))
    X = random_rows(tables, n=20)
    np.save(tmp_path / "X.npy", X)
    code = f"""
import json, sys
import numpy as np
from slam_predict.learn.robot.plain import PlainComponentModel
plain = PlainComponentModel.from_form(json.load(open({str(tmp_path / 'form.json')!r})))
out = plain.predict(np.load({str(tmp_path / 'X.npy')!r}))
print(json.dumps([out.tolist(),
                  sorted(m for m in sys.modules if m.split(".")[0] in ("sklearn", "joblib"))]))
"""
    proc = subprocess.run([sys.executable, "-c", code], cwd=root, capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    values, imported = json.loads(proc.stdout)
    assert imported == []
    np.testing.assert_allclose(values, model.predict(X), rtol=1e-9)
