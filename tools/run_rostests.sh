#!/usr/bin/env bash
# Run every tests/rostest/*.test with rostest inside the catkin workspace; prints a summary line.
set -uo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
set +u; source "$ROOT/setup.bash"; set -u
export ROS_HOME="${ROS_HOME:-$ROOT/out/ros_home}"
export ROS_LOG_DIR="$ROS_HOME/log"
mkdir -p "$ROS_LOG_DIR"
passed=0; failed=0
for test_file in "$ROOT"/tests/rostest/*.test; do
  [ -e "$test_file" ] || continue
  name="$(basename "$test_file")"
  if rostest --text slam_predict "$name" > "$ROS_HOME/$name.out" 2>&1 \
     && grep -q "RESULT: SUCCESS" "$ROS_HOME/$name.out"; then
    echo "rostest $name: PASSED"; passed=$((passed + 1))
  else
    echo "rostest $name: FAILED"; tail -40 "$ROS_HOME/$name.out"; failed=$((failed + 1))
  fi
done
echo "rostest: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
