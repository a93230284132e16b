"""Learning: datasets of per-building errors and features, the seed study's regression models
(+ a non-linear model and conformal intervals), the evaluation protocol, the model store and
prediction from a floor plan.

Modules: :mod:`dataset` (join + provenance), :mod:`estimators` / :mod:`conformal`
(scikit-learn estimators), :mod:`models` (model ids → estimators), :mod:`evaluate` (splits,
leave-one-out), :mod:`results` / :mod:`tables` / :mod:`plots` (output folder), :mod:`train`,
:mod:`store`, :mod:`featurize`, :mod:`predict`. Robot-aware models (issue #18):
:mod:`robot_inputs`, :mod:`robot_dataset`, :mod:`robot_config`, :mod:`robot_models`,
:mod:`robot_evaluate`, :mod:`robot_train`, :mod:`robot_predict`.
"""
