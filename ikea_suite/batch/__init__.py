"""ikea_suite.batch: the assembly task for the Cursor agent or a single arm
(arm_env.ROBOTS) in thousands of worlds with MJX.

    import jax, ikea_suite.batch
    env = ikea_suite.batch.load("table_four_leg_lack", num_worlds=1024)
    state = env.reset_batch(jax.random.PRNGKey(0), num_worlds=1024)
    state = env.step_batch(state, actions)        # (1024, 15) in [-1, 1]
    arm = ikea_suite.batch.load("table_four_leg_lack", robot="panda", num_worlds=1024)
    # arm actions (1024, 8): move_x..rotate_z, gripper, connect (batch/arm_env.py)

Built from the same model file, physics configuration, thresholds, rewards
and time limits as ikea_suite.load; the whole task (cursors, holding,
alignment, connect, groups, rewards, termination, placement) runs on the
device. Needs the `batch` (CPU) or `gpu` extra. See docs/batch.md for what differs
from the CPU task.
"""

from ikea_suite.batch.env import BatchAssembly
from ikea_suite.batch.env import State
from ikea_suite.batch.env import load

__all__ = ["BatchAssembly", "State", "load", "make_vector_env"]


def make_vector_env(furniture="table_four_leg_lack", num_envs=1, **options):
  """A gymnasium.vector.VectorEnv of `num_envs` batched worlds (see gym_vector.AssemblyVectorEnv);
  usable as the `vector_entry_point` of "ikea_suite/Assembly-v0". An arm of
  arm_env.ROBOTS as the `robot` option gives the batched arm (batch/arm_env.py)."""
  from ikea_suite.batch import gym_vector   # gymnasium is only needed here
  return gym_vector.AssemblyVectorEnv(furniture, num_envs, **options)
