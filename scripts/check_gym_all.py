"""Runs gymnasium's check_env on every robot x every category's representative furniture.

    python scripts/check_gym_all.py

tests/test_gym.py checks a fast subset (the Cursor on all representatives, each arm on
one); this covers all pairs and prints any warning besides the expected ones.
"""

import time
import warnings

from gymnasium.utils.env_checker import check_env

import ikea_suite
import ikea_suite.gym
from ikea_suite.props import catalog

# Every observation space is bounded (ikea_suite.observations): only the render modes that
# check_env cannot try without a render_mode are expected.
EXPECTED = ("Not able to test alternative render modes",)


def main():
  passed, failed, other, start = 0, 0, set(), time.perf_counter()
  for robot in ikea_suite.robot_names():
    for furniture in catalog.representatives():
      try:
        env = ikea_suite.gym.AssemblyEnv(furniture, robot)
        with warnings.catch_warnings(record=True) as caught:
          warnings.simplefilter("always")
          check_env(env)
        other |= {str(w.message) for w in caught if not any(e in str(w.message) for e in EXPECTED)}
        env.close()
        passed += 1
      except Exception as e:   # report every pair, not just the first failure
        failed += 1
        print(f"FAIL {robot} {furniture}: {e!r}")
  print(f"check_env: {passed} passed, {failed} failed of {passed + failed} pairs "
        f"in {time.perf_counter() - start:.0f} s; other warnings: {sorted(other) or 'none'}")


if __name__ == "__main__":
  main()
