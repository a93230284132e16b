"""Model store: ``models/<name>/`` = ``card.json`` + one joblib file per component.

Each ``<component>.joblib`` holds ``{model_id: fitted ConformalRegressor}``;
``<component>.plain.json`` holds the same models as plain arrays where they have such a form
(:mod:`slam_predict.learn.plain`), for predicting without importing scikit-learn. The card says what
the models were trained on (buildings, robot setting, SLAM config hash, feature version and
names, feature ranges), how they scored, which model is best per component, the library
versions, and the SHA-256 of every file. Loading checks the card, the checksums (a corrupt or
truncated file is refused before unpickling), the feature version and scikit-learn's major
version, and fails with one-line :class:`InputError` messages.

Checksums catch corruption, not tampering: like every pickle, a model file runs code when
loaded, so only load models from sources you trust.
"""
from __future__ import annotations

import contextlib
import hashlib
import importlib.metadata
import json
import logging
import os
import platform
import warnings
from pathlib import Path
from typing import Any

from slam_predict.atomic import atomic_dir
from slam_predict.errors import InputError, did_you_mean
from slam_predict.learn.card import CARD, FORMAT, is_robot_card, read_card

LOG = logging.getLogger(__name__)
__all__ = ["CARD", "FORMAT", "ModelStore", "read_card", "save_store"]


def installed(package: str) -> str:
    """Installed version of a distribution (cheap: no import of the package)."""
    try:
        return importlib.metadata.version(package)
    except importlib.metadata.PackageNotFoundError:
        return "?"


def library_versions() -> dict[str, str]:
    """Versions of the libraries a pickled model depends on."""
    from slam_predict import __version__

    return {"python": platform.python_version(), "numpy": installed("numpy"),
            "scipy": installed("scipy"), "scikit-learn": installed("scikit-learn"),
            "joblib": installed("joblib"), "slam_predict": __version__}


def sha256(path: os.PathLike | str) -> str:
    """Hex SHA-256 of a file."""
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def evaluation_r2(metrics: dict[str, Any]) -> list[float]:
    """The R² scores of a card's model metrics: mean over random splits and leave-one-out."""
    values = [metrics.get("r2_mean"), (metrics.get("leave_one_out") or {}).get("r2")]
    return [float(v) for v in values if isinstance(v, (int, float))]


def skilful(metrics: dict[str, Any]) -> bool:
    """True unless an evaluation R² of the model is ≤ 0 (or NaN): such a model predicts no
    better than the training buildings' mean and is not offered as best."""
    return all(r2 > 0 for r2 in evaluation_r2(metrics))


SHIPPED_MODELS = Path(__file__).resolve().parents[3] / "models"   # the package's models/
MODELS_ENV = "SLAM_PREDICT_MODELS"


def default_models_dir() -> Path:
    """``$SLAM_PREDICT_MODELS`` or the package's ``models/`` folder."""
    env = os.environ.get(MODELS_ENV)
    if env:
        return Path(env)
    return SHIPPED_MODELS


def save_store(path: os.PathLike | str, card: dict[str, Any],
               estimators: dict[str, dict[str, Any]],
               plain: dict[str, dict[str, Any]] | None = None,
               extra_files: dict[str, str] | None = None) -> Path:
    """Write a model folder atomically: per component a joblib file (and the plain forms of
    its models, if any), the ``extra_files`` (name → text), then the card; every file's
    SHA-256 goes into the card."""
    path = Path(path)
    card = dict(card, format=FORMAT, versions=library_versions(), files={})
    with atomic_dir(path) as tmp:
        os.chmod(tmp, 0o755)  # mkdtemp makes it private; models are for every user
        for component, models in estimators.items():
            name = f"{component}.joblib"
            import joblib

            joblib.dump(dict(models), tmp / name, compress=3)
            card["files"][name] = sha256(tmp / name)
            if plain and plain.get(component):
                name = f"{component}.plain.json"
                (tmp / name).write_text(json.dumps(plain[component]) + "\n")
                card["files"][name] = sha256(tmp / name)
        for name, text in (extra_files or {}).items():
            (tmp / name).write_text(text, encoding="utf-8")
            card["files"][name] = sha256(tmp / name)
        (tmp / CARD).write_text(json.dumps(card, indent=2, sort_keys=False) + "\n")
    LOG.info("model %s written to %s", card.get("name"), path)
    return path


def check_compatible(card: dict[str, Any], card_path: Path,
                     feature_version: str | None) -> list[str]:
    """Raise InputError for incompatible models; returns warnings for minor differences."""
    current = installed("scikit-learn")
    trained = str(card["versions"].get("scikit-learn", "?"))
    if trained.split(".")[0] != current.split(".")[0]:
        raise InputError(f"model trained with scikit-learn {trained}, installed "
                         f"{current} (different major version); retrain with "
                         "'slam-predict learn train'", card_path)
    if feature_version is not None and card["feature_version"] != feature_version:
        raise InputError(f"model uses feature version {card['feature_version']}, this "
                         f"slam_predict computes {feature_version}; retrain with "
                         "'slam-predict learn train'", card_path)
    notes = []
    if trained != current:
        notes.append(f"model trained with scikit-learn {trained}, installed {current}")
    return notes


class ModelStore:
    """A loaded model folder: its card and (lazily) its fitted estimators."""

    def __init__(self, path: os.PathLike | str, feature_version: str | None = None):
        self.path = Path(path)
        self.card = read_card(self.path)
        self.notes = check_compatible(self.card, self.path / CARD, feature_version)
        for name in self.card["files"]:  # refuse a damaged folder whole, used file or not
            self._checked(name)
        self._loaded: dict[str, dict[str, Any]] = {}

    @property
    def name(self) -> str:
        return str(self.card["name"])

    def best(self, component: str) -> str:
        """The best model id of ``component``."""
        return str(self._component(component)["best"])

    def offered(self, component: str) -> str | None:
        """The best model id of ``component`` when it is :func:`skilful`, else None (also
        when the card has no model of the component)."""
        comp = self.card["components"].get(component)
        if not isinstance(comp, dict) or comp.get("best") not in comp.get("models", {}):
            return None
        best = str(comp["best"])
        return best if skilful(comp["models"][best].get("metrics") or {}) else None

    def _component(self, component: str) -> dict[str, Any]:
        comps = self.card["components"]
        if component not in comps:
            raise InputError(f"model has no component '{component}'" +
                             did_you_mean(component, comps), self.path / CARD)
        return comps[component]

    def estimator(self, component: str, model_id: str | None = None):
        """The fitted (conformal) estimator of ``component`` (default: its best model)."""
        model_id = model_id or self.best(component)
        models = self._load(component)
        if model_id not in models:
            raise InputError(f"model '{model_id}' not stored for {component}"
                             + did_you_mean(model_id, models), self.path)
        return models[model_id]

    def plain(self, component: str, model_id: str) -> dict[str, Any] | None:
        """The plain-array form of a model (:mod:`plain`), or None when it has none."""
        entry = self._component(component)["models"].get(model_id, {})
        if not entry.get("plain"):
            return None
        key = f"{component}.plain.json"
        if key not in self._loaded:
            text = self._checked(key).read_text(encoding="utf-8")
            try:
                self._loaded[key] = json.loads(text)
            except json.JSONDecodeError:
                raise InputError("corrupt model file (invalid JSON)", self.path / key) from None
        form = self._loaded[key].get(model_id)
        if not isinstance(form, dict):
            raise InputError(f"corrupt model file (no plain form of {model_id})",
                             self.path / key)
        return form

    def checked_text(self, name: str) -> str:
        """The text of a model file whose checksum matches the card (InputError otherwise)."""
        return self._checked(name).read_text(encoding="utf-8")

    def _checked(self, name: str) -> Path:
        """Path of a model file whose checksum matches the card."""
        file = self.path / name
        if not file.is_file():
            raise InputError("model file missing", file)
        if self.card["files"].get(name) != sha256(file):
            raise InputError("corrupt model file (checksum differs from card.json)", file)
        return file

    def _load(self, component: str) -> dict[str, Any]:
        if component in self._loaded:
            return self._loaded[component]
        self._component(component)
        file = self._checked(f"{component}.joblib")
        import joblib

        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # minor-version pickles: reported in notes
                with _pickle_names(self.card):
                    models = joblib.load(file)
        except Exception as exc:  # noqa: BLE001 — any unpickling failure means unusable
            raise InputError(f"corrupt model file ({exc.__class__.__name__})", file) from None
        if not isinstance(models, dict):
            raise InputError("corrupt model file (not a model dictionary)", file)
        self._loaded[component] = models
        return models


def _pickle_names(card: dict[str, Any]):
    """The module names a pickle of this card's family may use (robot-aware folders written
    before ``learn/robot/`` name its modules ``learn.robot_<module>``)."""
    if not is_robot_card(card):
        return contextlib.nullcontext()
    from slam_predict.learn.robot import legacy_module_names

    return legacy_module_names()


def list_stores(models_dir: os.PathLike | str) -> list[Path]:
    """Model folders (with a card.json) under ``models_dir``, sorted by name."""
    models_dir = Path(models_dir)
    if not models_dir.is_dir():
        return []
    return sorted(p for p in models_dir.iterdir() if (p / CARD).is_file())
