"""scikit-learn's estimator contract (parametrize_with_checks) for every estimator we define."""
from __future__ import annotations

from sklearn.ensemble import RandomForestRegressor
from sklearn.utils.estimator_checks import parametrize_with_checks

from slam_predict.learn.estimators import (
    ConformalRegressor,
    ElasticNetGridCV,
    FRegressionVoting,
    SingleFeatureLinear,
)

ESTIMATORS = [
    SingleFeatureLinear(feature=0),
    FRegressionVoting(n_subsets=10, max_k=3),
    FRegressionVoting(k=1, n_subsets=10),
    ElasticNetGridCV(cv=3),
    ConformalRegressor(),
    ConformalRegressor(method="split", conformity="scaled"),
    ConformalRegressor(ElasticNetGridCV(cv=3), cv=3),
    ConformalRegressor(RandomForestRegressor(n_estimators=5, random_state=0), cv=3),
]


@parametrize_with_checks(ESTIMATORS)
def test_sklearn_contract(estimator, check):
    check(estimator)
