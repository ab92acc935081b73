"""Hashes whole scripted-expert episodes, so a refactor can show it changed no behaviour.

    python scripts/episode_hashes.py            # one episode per arm, plus the Cursor oracle
    python scripts/episode_hashes.py --steps 400

Each line: robot, furniture, seed, steps run, connections made, and a SHA-256 over every
step's action, reward and the full physics state (qpos, qvel, act, ctrl, eq_active). Two
runs of the same code on the same machine print the same lines; a change that alters any
number of any step prints a different hash.
"""

import argparse
import hashlib

import numpy as np

import ikea_suite
from ikea_suite import experts

# (robot, furniture, scale, seed): one per arm and the Cursor, on models each expert assembles.
EPISODES = (("cursor", "table_four_leg_lack", 1.0, 3),
            ("sawyer", "table_four_leg_lack", 0.5, 3),
            ("panda", "stool_round_frosta", 0.5, 3),
            ("jaco", "box_open_kuggis", 0.5, 3),
            ("baxter", "table_four_leg_lack", 0.5, 3))


def episode_hash(robot: str, furniture: str, scale: float, seed: int,
                 max_steps: int) -> tuple[int, int, str]:
  """(steps, connections, hex digest) of the expert's episode, cut at max_steps."""
  env = ikea_suite.load(furniture, robot, seed=seed, scale=scale)
  expert = experts.make_expert(env)
  timestep = env.reset()
  expert.reset()
  digest = hashlib.sha256()
  steps = 0
  while not timestep.last() and steps < max_steps:
    action = np.asarray(expert(timestep), dtype=float)
    timestep = env.step(action)
    data = env.physics.data
    for array in (action, np.float64(timestep.reward or 0.0), data.qpos, data.qvel, data.act,
                  data.ctrl, data.eq_active):
      digest.update(np.ascontiguousarray(array).tobytes())
    steps += 1
  return steps, len(env.task.state.connections), digest.hexdigest()


def main() -> None:
  parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
  parser.add_argument("--steps", type=int, default=100_000, help="cut each episode here")
  args = parser.parse_args()
  for robot, furniture, scale, seed in EPISODES:
    steps, connections, digest = episode_hash(robot, furniture, scale, seed, args.steps)
    print(f"{robot:7s} {furniture:24s} seed {seed} steps {steps:5d} "
          f"connections {connections:2d} {digest}", flush=True)


if __name__ == "__main__":
  main()
