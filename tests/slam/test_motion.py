"""GMapping's motion model: sample means and standard deviations match the formulas."""
import numpy as np
import pytest

from slam_predict.geometry import compose
from slam_predict.slam.gmapping.motion import draw_from_motion, noise_stds, odometry_step, travelled


@pytest.mark.parametrize("step", [(0.5, 0.1, 0.2), (-0.3, 0.0, -0.6), (0.0, 0.0, 0.4)])
def test_noisy_steps_have_the_documented_mean_and_std(step):
    p_old = np.array([1.0, 2.0, 0.3])
    p_new = compose(p_old, np.array(step))
    srr, srt, str_, stt = 0.1, 0.2, 0.1, 0.2
    rng = np.random.default_rng(4)
    out = draw_from_motion(np.zeros((40000, 3)), p_new, p_old, srr, srt, str_, stt, rng)
    dx, dy, dth = step
    sx = srr * abs(dx) + str_ * abs(dth) + 0.3 * srr * abs(dy)
    sy = srr * abs(dy) + str_ * abs(dth) + 0.3 * srr * abs(dx)
    sth = stt * abs(dth) + srt * np.hypot(dx, dy)
    assert np.allclose(noise_stds(odometry_step(p_new, p_old), srr, srt, str_, stt),
                       (sx, sy, sth))
    # particles start at the origin with yaw 0, so their new poses are the noisy steps
    assert np.allclose(out.mean(axis=0), step, atol=4 * np.array([sx, sy, sth]) / 200 + 1e-12)
    assert np.allclose(out.std(axis=0), (sx, sy, sth), rtol=0.03, atol=1e-12)


def test_step_is_applied_in_each_particles_frame():
    p_old = np.array([0.0, 0.0, 0.0])
    p_new = np.array([1.0, 0.0, 0.0])
    poses = np.array([[0.0, 0.0, np.pi / 2], [5.0, 5.0, np.pi]])
    out = draw_from_motion(poses, p_new, p_old, 0, 0, 0, 0, np.random.default_rng(0))
    assert np.allclose(out[:, :2], [[0.0, 1.0], [4.0, 5.0]])


def test_zero_motion_keeps_poses_and_draws_nothing():
    rng = np.random.default_rng(1)
    state = rng.bit_generator.state
    poses = np.array([[1.0, 2.0, 3.0]])
    out = draw_from_motion(poses, [0.2, 0.1, 0.3], [0.2, 0.1, 0.3], 0.1, 0.2, 0.1, 0.2, rng)
    assert np.array_equal(out, poses)
    assert rng.bit_generator.state == state


def test_travelled_wraps_the_rotation():
    lin, ang = travelled([1.0, 1.0, 3.1], [0.0, 1.0, -3.1])
    assert lin == pytest.approx(1.0)
    assert ang == pytest.approx(2 * np.pi - 6.2)
