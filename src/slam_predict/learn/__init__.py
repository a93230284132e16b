"""Learning: datasets of per-building errors and features, the seed study's regression models
(+ a non-linear model and conformal intervals), the evaluation protocol, the model store and
prediction from a plan's feature vector.

Modules: :mod:`dataset` (the one dataset format of both families: join, provenance, optional
robot and SLAM-algorithm columns), :mod:`sources` (the error and feature tables a dataset is
built from), :mod:`estimators` / :mod:`conformal`
(scikit-learn estimators), :mod:`models` (model ids → estimators), :mod:`evaluate` (splits,
leave-one-out), :mod:`results` / :mod:`tables` / :mod:`plots` (output folder), :mod:`train`,
:mod:`card` (the model card of both families), :mod:`store`, :mod:`model`
(:func:`load_model`), :mod:`featurize`, :mod:`predict`. Robot-aware models (issue #18): the
subpackage :mod:`slam_predict.learn.robot`.
"""
from slam_predict.learn.model import load_model

__all__ = ["load_model"]
