"""Dense reward: staged shaping towards the next connection, as a potential.

`load(..., reward="dense")` replaces the sparse reward (sparse stays the
default). The dense reward is potential-based shaping (Ng, Harada, Russell
1999): with a potential `Phi(s)` the step reward is `Phi(s') - Phi(s)`, so
it cannot be farmed by hovering, and an episode's return telescopes to
`Phi(end) - Phi(start)` whatever the furniture.

    Phi = connection_reward * (connections made + best pair progress) / connections needed

Pair progress, for every open connector pair that would grow the root
part's assembly (every open pair if none does), with `moving` the part that
joins it, is the weighted sum of named stage terms, each in [0, 1]:

| term | weight | value |
|---|---|---|
| `reach` | 0.10 | 1 when a gripper holds `moving`, else exp(-d / 0.25 m), d the nearest tool (cursor or TCP) to its centre of mass |
| `grasp` | 0.10 | 1 when a gripper holds `moving`'s group (Cursor: selects it; arms: two finger bodies touch it) |
| `lift` | 0.10 | held, and raised: (z - z at episode start) / 0.1 m, clipped |
| `distance` | 0.30 | held, and the connectors closer: exp(-gap / 0.25 m) |
| `angle` | 0.10 | held, and the connectors aligned: (1 + cos up) / 2 * (1 + cos forward) / 2 |

The best pair counts, so any interchangeable part the agent works on is
rewarded. The stage weights sum to 0.7: the remaining 0.3 of a connection
is paid only by connecting (`connect`). On completion the `complete` term
pays min(completion_bonus, connection_reward) once.

So a complete episode returns about 2 x `connection_reward` for any
furniture (less the starting potential), and no step pays more than the
sparse reward would for a connection: a connection step pays at most
connection_reward * (1 + 0.7) / needed (<= connection_reward for two or more
needed connections; with one, the pair potential after it is 0). Releasing
a part or pulling connectors apart costs what approaching them paid.
"""

import dataclasses

import numpy as np

from ikea_suite import errors
from ikea_suite.tasks import planner

REACH_SCALE = 0.25     # metres: reach term is exp(-d / REACH_SCALE)
LIFT_HEIGHT = 0.1      # metres of lift that earn the whole lift term
DISTANCE_SCALE = 0.25  # metres: distance term is exp(-gap / DISTANCE_SCALE)


@dataclasses.dataclass(frozen=True)
class StageWeights:
  """Share of one connection each stage term earns; the rest is paid by connecting."""
  reach: float = 0.1
  grasp: float = 0.1
  lift: float = 0.1
  distance: float = 0.3
  angle: float = 0.1

  @property
  def total(self) -> float:
    return self.reach + self.grasp + self.lift + self.distance + self.angle


class DenseReward:
  """Computes the dense step reward of an `Assembly` task; `reset` at each episode start.

  Args:
    task: the `Assembly` task (its furniture, robot, state, alignment and root part).
    connection_reward: the sparse reward of one connection; the dense scale.
    completion_bonus: the sparse completion bonus; dense pays at most connection_reward of it.
    weights: the stage terms' shares of one connection.
  """

  def __init__(self, task, connection_reward: float, completion_bonus: float,
               weights: StageWeights = StageWeights()):
    self._task = task
    self._scale = float(connection_reward)
    self._complete_bonus = min(float(completion_bonus), float(connection_reward))
    self._weights = weights
    self._needed = max(len(task.furniture.parts) - 1, 1)
    self._start_height = None
    self._potential = 0.0
    self._was_complete = False
    self.terms = {}

  def reset(self, physics) -> None:
    """Records the parts' starting heights and the starting potential."""
    physics.forward()   # the initializer moved parts; derived positions are stale
    com = physics.data.xipos[self._task.furniture.body_ids]
    self._start_height = com[:, 2].copy()
    self._was_complete = self._task.state.complete
    self._potential = self.potential(physics)

  def pair_terms(self, physics) -> dict[str, np.ndarray]:
    """Stage terms (each in [0, 1]) of every candidate (pair, moving part); may be empty."""
    task = self._task
    table, state, furniture = task.furniture.connectors, task.state, task.furniture
    open_mask = planner.open_pairs(table, state)
    labels = state.group_labels()
    root_group = labels[task.root_part]
    part_a, part_b = table.part[table.pair_a], table.part[table.pair_b]
    grows = open_mask & ((labels[part_a] == root_group) | (labels[part_b] == root_group))
    allowed = grows if grows.any() else open_mask
    # Each pair twice: the moving part is the one outside the root group (either, if none is).
    pairs = np.concatenate([np.flatnonzero(allowed), np.flatnonzero(allowed)])
    moving = np.concatenate([part_b[allowed], part_a[allowed]])
    keep = labels[moving] != root_group
    if grows.any():
      pairs, moving = pairs[keep], moving[keep]
    scores = task.alignment(physics)
    by_tool = task.robot.held_parts_by_tool(physics, furniture.body_ids)
    held = np.isin(labels, labels[by_tool.any(axis=0)])[moving].astype(float)
    com = physics.data.xipos[furniture.body_ids]
    tools = task.robot.tool_positions(physics)
    # A tool busy holding another group (the Cursor's base holding the assembly)
    # is no help in reaching the moving part, so it does not count.
    tool_group = np.where(by_tool.any(axis=1), labels[np.argmax(by_tool, axis=1)], -1)
    free = (tool_group[None] < 0) | (tool_group[None] == labels[moving][:, None])
    gaps = np.linalg.norm(com[moving][:, None, :] - tools[None], axis=-1)
    nearest = np.min(np.where(free, gaps, np.inf), axis=1)
    reach = np.maximum(held, np.exp(-nearest / REACH_SCALE))
    lift = held * np.clip((com[moving, 2] - self._start_height[moving]) / LIFT_HEIGHT, 0.0, 1.0)
    distance = held * np.exp(-scores.distance[pairs] / DISTANCE_SCALE)
    angle = held * (1 + scores.up_cos[pairs]) / 2 * (1 + scores.forward_cos[pairs]) / 2
    return {"reach": reach, "grasp": held, "lift": lift, "distance": distance, "angle": angle}

  def pair_progress(self, physics) -> float:
    """The best candidate pair's weighted stage terms, in [0, weights.total]."""
    terms = self.pair_terms(physics)
    if not len(terms["grasp"]):
      self.terms = {name: 0.0 for name in terms}
      return 0.0
    w = self._weights
    progress = (w.reach * terms["reach"] + w.grasp * terms["grasp"] + w.lift * terms["lift"]
                + w.distance * terms["distance"] + w.angle * terms["angle"])
    best = int(np.argmax(progress))
    self.terms = {name: float(values[best]) for name, values in terms.items()}
    return float(progress[best])

  def potential(self, physics) -> float:
    """Phi: connection_reward x (connections + best pair progress) / connections needed."""
    made = len(self._task.state.connections)
    return self._scale * (made + self.pair_progress(physics)) / self._needed

  def reward(self, physics) -> float:
    """The dense reward of the step just taken: the potential's change, plus completion once."""
    if self._start_height is None:
      raise errors.IkeaSuiteError("DenseReward.reset must run at the episode start")
    potential = self.potential(physics)
    reward = potential - self._potential
    self._potential = potential
    complete = self._task.state.complete
    if complete and not self._was_complete:
      reward += self._complete_bonus
    self._was_complete = complete
    return reward


def make(name: str, task, connection_reward: float, completion_bonus: float):
  """A DenseReward for "dense", None for "sparse" (the task's own reward): `name` is a
  config.TaskConfig's `reward`, one of config.REWARDS."""
  if name == "sparse":
    return None
  return DenseReward(task, connection_reward, completion_bonus)
