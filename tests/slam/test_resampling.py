"""Weights, Neff and systematic resampling as GridSlamProcessor does them."""
import numpy as np
import pytest

from slam_predict.slam.gmapping.filter import normalized_weights, pose_entropy, systematic_resample


def slow_resample(weights, u):
    """uniform_resampler::resampleIndexes written as the upstream loop."""
    n = len(weights)
    interval = sum(weights) / n
    target = interval * u
    out, cum = [], 0.0
    for i, w in enumerate(weights):
        cum += w
        while cum > target:
            out.append(i)
            target += interval
    return out + [0] * (n - len(out))


@pytest.mark.parametrize("seed", range(5))
def test_systematic_resampling_keeps_the_expected_counts(seed):
    rng = np.random.default_rng(seed)
    w = rng.random(30) ** 3
    w /= w.sum()
    u = rng.random()
    idx = systematic_resample(w, u)
    assert list(idx) == slow_resample(list(w), u)
    counts = np.bincount(idx, minlength=30)
    expected = 30 * w
    assert np.all(counts >= np.floor(expected) - 1e-9) and np.all(counts <= np.ceil(expected))
    assert counts.sum() == 30 and np.all(np.diff(idx) >= 0)


def test_resampling_counts_average_to_n_times_the_weights():
    w = np.array([0.5, 0.25, 0.125, 0.125])
    rng = np.random.default_rng(0)
    counts = sum(np.bincount(systematic_resample(w, rng.random()), minlength=4)
                 for _ in range(2000))
    assert np.allclose(counts / 2000, 4 * w, atol=0.03)


def test_weights_use_ogain_and_particle_count():
    logw = np.array([-10.0, -13.0, -19.0])
    w, neff = normalized_weights(logw, ogain=3.0)
    raw = np.exp((logw - logw.max()) / (3.0 * 3))
    assert np.allclose(w, raw / raw.sum())
    assert neff == pytest.approx(1.0 / np.sum(w ** 2))
    assert normalized_weights(np.zeros(5), 3.0)[1] == pytest.approx(5.0)


def test_entropy_follows_slam_gmapping():
    assert pose_entropy(np.zeros(4)) == 0.0
    w = np.array([-1.0, -1.0])
    assert pose_entropy(w) == pytest.approx(np.log(2))
