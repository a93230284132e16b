"""World.extent against the centres of its corner cells."""
import numpy as np

from slam_predict.world.model import World


def test_extent_is_half_a_cell_beyond_the_corner_cell_centres():
    world = World("w", np.zeros((30, 50), bool), 0.05, origin=(1.5, -2.0))
    xmin, ymin, xmax, ymax = world.extent
    top_left, bottom_right = world.cell_to_world([[0, 0], [29, 49]])
    np.testing.assert_allclose([xmin, ymax], top_left + [-0.025, 0.025], atol=1e-12)
    np.testing.assert_allclose([xmax, ymin], bottom_right + [0.025, -0.025], atol=1e-12)
    assert np.allclose([xmax - xmin, ymax - ymin], world.size_m)
    assert world.world_to_cell([xmin + 1e-9, ymax - 1e-9]).tolist() == [0, 0]
