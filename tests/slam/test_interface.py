"""The SLAM interface and registry; the gmapping back-end on a synthetic drive."""
import numpy as np
import pytest
from slam_scan import ANGLES, scan_of

from slam_predict.errors import InputError
from slam_predict.geometry import compose, inverse
from slam_predict.slam import LaserGeometry, SlamBackend, available, create, register
from slam_predict.slam.compare import apply_transform, map_agreement, rigid_fit
from slam_predict.slam.gmapping.params import GMappingParams


def test_registry_by_name():
    assert "gmapping" in available()
    with pytest.raises(ValueError):
        register("gmapping", SlamBackend)
    with pytest.raises(InputError, match="did you mean 'gmapping'"):
        create("gmaping")


def drive(n=80):
    """Ground-truth laser poses around the synthetic room and drifting odometry."""
    s = np.linspace(0, 1, n)
    truth = np.stack([-3.0 + 6.0 * s, -2.5 + 0.5 * np.sin(6 * s), 0.3 * np.cos(5 * s)], axis=1)
    odom = [truth[0]]
    for k in range(1, n):
        step = compose(inverse(truth[k - 1]), truth[k])
        step = step * np.array([1.05, 1.0, 1.1]) + np.array([0.0, 0.01, 0.01])  # biased odometry
        odom.append(compose(odom[-1], step))
    return truth, np.array(odom)


def test_gmapping_backend_tracks_a_synthetic_drive():
    truth, odom = drive()
    laser = LaserGeometry(ANGLES, (0.0, 0.0, 0.0), 30.0)
    params = GMappingParams(particles=10, linearUpdate=0.2, angularUpdate=0.1, srr=0.05, srt=0.1,
                            str=0.05, stt=0.1)
    slam = create("gmapping", params=params, laser=laser, rng=np.random.default_rng(5))
    out = []
    for k in range(len(truth)):
        pose = slam.update(odom[k], scan_of(truth[k]), float(k) * 0.1)
        if pose is not None:
            out.append((k, pose))
            assert np.allclose(compose(slam.map_to_odom(), odom[k]), pose)
    assert len(out) > 20
    idx = np.array([k for k, _ in out])
    numbers, t, traj = slam.trajectory()
    assert len(traj) == len(out) and np.allclose(t, idx * 0.1)
    fitted = apply_transform(rigid_fit(traj, truth[idx]), traj)
    assert np.max(np.hypot(*(fitted - truth[idx])[:, :2].T)) < 0.1
    raw = apply_transform(rigid_fit(odom[idx], truth[idx]), odom[idx])
    assert np.max(np.hypot(*(raw - truth[idx])[:, :2].T)) > 0.3  # odometry alone drifts
    grid = slam.map()
    assert (grid.data == 100).sum() > 200 and grid.resolution == 0.05
    assert np.allclose(slam.pose(), compose(slam.map_to_odom(), odom[-1]))  # tf map→base_link
    assert slam.entropy() >= 0.0 and slam.stats()["scans_processed"] == len(out)


def test_map_agreement_counts_near_cells():
    a = np.zeros((20, 20), dtype=np.int8)
    b = np.zeros((20, 20), dtype=np.int8)
    a[5, 5:15] = 100
    b[7, 5:15] = 100       # 2 cells away: near
    b[15, 0:10] = 100      # far from a
    near_a, near_b = map_agreement(a, b, tol=2.0)
    assert near_a == 1.0 and near_b == pytest.approx(0.5)
    assert map_agreement(a, b, tol=1.0)[0] == 0.0


def test_rigid_fit_recovers_a_transform():
    rng = np.random.default_rng(1)
    pts = np.c_[rng.normal(size=(30, 2)) * 5, rng.normal(size=30)]
    t = np.array([1.5, -2.0, 0.7])
    assert np.allclose(rigid_fit(pts, apply_transform(t, pts)), t)
