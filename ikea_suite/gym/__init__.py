"""gymnasium adapter: `import ikea_suite.gym` registers `ikea_suite/Assembly-v0`.

    import gymnasium, ikea_suite.gym
    env = gymnasium.make("ikea_suite/Assembly-v0", furniture="table_four_leg_lack",
                         robot="cursor", reward="dense")

Needs the `gym` extra (`pip install "ikea_suite[gym]"`). The time limit is
the suite's own (`time_limit` option), reported as `truncated`; no gymnasium
TimeLimit wrapper is added, and `env.spec.max_episode_steps` is that limit in steps.

    envs = gymnasium.make_vec("ikea_suite/Assembly-v0", num_envs=1024,
                              vectorization_mode="vector_entry_point")

gives the batched environment (ikea_suite.batch, MJX; the `batch` or `gpu` extra), with
the same observation keys, shapes, dtypes and info keys as the CPU environment.
"""

import gymnasium

from ikea_suite.gym.env import AssemblyEnv
from ikea_suite.gym.env import ResetNeeded

ENV_ID = "ikea_suite/Assembly-v0"

if ENV_ID not in gymnasium.registry:
  gymnasium.register(id=ENV_ID, entry_point="ikea_suite.gym.env:AssemblyEnv",
                     vector_entry_point="ikea_suite.batch:make_vector_env")

__all__ = ["AssemblyEnv", "ENV_ID", "ResetNeeded"]
