"""One episode as arrays: what a demonstration stores, step by step.

Step t holds the state and observation before action t (`states[t]`,
`obs[t]`), the action, the reward and done after it, and `next_obs[t]`.
Subtask labels per step: the expert's phase and the part it is bringing
in, the planner's suggested [moving, target] part pair, the connector pair
connected by this step (-1, -1 when none) and the connections made so far.
"""

import dataclasses
from collections.abc import Callable

import dm_env
import numpy as np

from ikea_suite import environment
from ikea_suite.datasets import mj_state

NO_PAIR = (-1, -1)


@dataclasses.dataclass
class Episode:
  """A recorded episode; every array has the number of steps as its first axis."""
  seed: int
  actions: np.ndarray
  rewards: np.ndarray
  dones: np.ndarray
  states: np.ndarray
  obs: dict[str, np.ndarray]
  next_obs: dict[str, np.ndarray]
  subtask: dict[str, np.ndarray]
  success: bool

  @property
  def num_samples(self) -> int:
    """Number of steps (actions) in the episode."""
    return len(self.actions)


class EpisodeRecorder:
  """Accumulates steps of one episode of `env`; `finish` returns the `Episode`.

  Args:
    env: the ikea_suite environment being recorded.
    seed: the seed its random state was set to before `reset` (stored with the demo).
  """

  def __init__(self, env: environment.Environment, seed: int):
    self._env, self._seed = env, int(seed)
    self._steps = {name: [] for name in ("actions", "rewards", "dones", "states")}
    self._obs, self._next_obs = [], []
    self._labels = {name: [] for name in ("phase", "part", "next_pair", "connected_pair",
                                          "connections")}

  def before_step(self, observation: dict[str, np.ndarray]) -> None:
    """Stores the state and observation the next action is taken from."""
    self._steps["states"].append(mj_state.get_state(self._env.physics))
    self._obs.append({k: np.array(v) for k, v in observation.items()})
    self._made = len(self._env.task.state.connections)

  def after_step(self, action: np.ndarray, timestep: dm_env.TimeStep, phase: str = "",
                 part: int = -1) -> None:
    """Stores the action, its outcome and the subtask labels of the step just taken.

    Args:
      action: the action just sent.
      timestep: what env.step returned for it.
      phase: the expert's phase name ("" for none).
      part: the part the expert is bringing in, -1 for none.
    """
    task = self._env.task
    self._steps["actions"].append(np.asarray(action, dtype=np.float64))
    self._steps["rewards"].append(float(timestep.reward))
    self._steps["dones"].append(bool(timestep.last()))
    self._next_obs.append({k: np.array(v) for k, v in timestep.observation.items()})
    connections = task.state.connections
    self._labels["phase"].append(phase)
    self._labels["part"].append(int(part))
    self._labels["next_pair"].append(np.asarray(task.suggested_parts(), dtype=np.int64))
    made = connections[-1] if len(connections) > self._made else NO_PAIR
    self._labels["connected_pair"].append(np.asarray(made, dtype=np.int64))
    self._labels["connections"].append(len(connections))

  def finish(self) -> Episode:
    """The recorded episode as stacked arrays."""
    def stack(frames):
      return {k: np.stack([f[k] for f in frames]) for k in frames[0]}
    labels = {k: np.asarray(v) for k, v in self._labels.items()}
    labels["phase"] = labels["phase"].astype("S")
    return Episode(
        seed=self._seed, actions=np.stack(self._steps["actions"]),
        rewards=np.asarray(self._steps["rewards"]), dones=np.asarray(self._steps["dones"]),
        states=np.stack(self._steps["states"]), obs=stack(self._obs),
        next_obs=stack(self._next_obs), subtask=labels,
        success=bool(self._env.task.state.complete))


def record_episode(env: environment.Environment, policy: Callable, seed: int,
                   subtask: Callable[[], tuple[str, int]] | None = None) -> Episode:
  """Runs one episode of `policy` from the random state `seed` and records it.

  Args:
    env: an ikea_suite environment.
    policy: maps a TimeStep to an action; its `reset()` is called first if it has one.
    seed: the environment's random state is seeded with it before `reset`, so the
      episode starts as `ikea_suite.load(..., seed=seed)` would.
    subtask: returns (phase, part) of the policy's current subtask after each action.

  Returns:
    The recorded `Episode`.
  """
  env.random_state.seed(int(seed))
  timestep = env.reset()
  if hasattr(policy, "reset"):
    policy.reset()
  recorder = EpisodeRecorder(env, seed)
  while not timestep.last():
    recorder.before_step(timestep.observation)
    action = policy(timestep)
    phase, part = subtask() if subtask else ("", -1)
    timestep = env.step(action)
    recorder.after_step(action, timestep, phase, part)
  return recorder.finish()
