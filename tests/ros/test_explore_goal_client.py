"""The explore node's goal client: one goal handle tracked by the client itself, statuses read
from it as SimpleActionClient.get_state() folds them, and no transition callbacks (an old goal's
late status updates must reach nobody, where SimpleActionClient logs an ERROR for each)."""
from __future__ import annotations

import pytest

from slam_predict.ros.explore_node import ActionGoalClient

PENDING, ACTIVE, PREEMPTED, SUCCEEDED, ABORTED = 0, 1, 2, 3, 4
REJECTED, PREEMPTING, RECALLING, RECALLED, LOST = 5, 6, 7, 8, 9


class FakeHandle:
    def __init__(self):
        self.status = PENDING
        self.cancelled = False

    def get_goal_status(self):
        return self.status

    def cancel(self):
        self.cancelled = True


class FakeActionClient:
    """actionlib.ActionClient's send_goal: a handle per goal; callbacks are remembered."""

    def __init__(self):
        self.handles, self.callbacks = [], []

    def send_goal(self, goal, transition_cb=None, feedback_cb=None):
        self.callbacks.append((transition_cb, feedback_cb))
        self.handles.append(FakeHandle())
        return self.handles[-1]


@pytest.fixture()
def client():
    return ActionGoalClient(FakeActionClient(), robot_pose=lambda: (0.0, 0.0, 0.0))


def test_no_goal_no_status(client):
    assert client.status() is None
    client.cancel(0.0)            # nothing to cancel


@pytest.mark.parametrize("raw, seen", [(PENDING, PENDING), (ACTIVE, ACTIVE),
                                       (PREEMPTED, PREEMPTED), (SUCCEEDED, SUCCEEDED),
                                       (ABORTED, ABORTED), (REJECTED, ABORTED),
                                       (PREEMPTING, ACTIVE), (RECALLING, PENDING),
                                       (RECALLED, PREEMPTED), (LOST, ABORTED)])
def test_statuses_fold_as_simple_action_client_then_explorer(client, raw, seen):
    client.send_goal((1.0, 2.0, 0.0), 0.0)
    client.client.handles[-1].status = raw
    assert client.status() == seen


def test_a_replaced_goal_is_no_longer_read_or_called_back(client):
    client.send_goal((1.0, 2.0, 0.0), 0.0)
    old = client.client.handles[-1]
    old.status = ACTIVE
    client.send_goal((3.0, 4.0, 0.0), 1.0)
    old.status = PREEMPTED               # move_base's late report on the replaced goal
    assert client.status() == PENDING    # the new goal's
    assert client.client.callbacks == [(None, None), (None, None)]
    client.cancel(2.0)
    assert client.client.handles[-1].cancelled and not old.cancelled
    assert client.plan_length() == pytest.approx(5.0)
