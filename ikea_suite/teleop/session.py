"""A teleoperation session: key presses in, control steps out, episodes recorded.

The viewer thread only queues key codes (`on_key`); the main loop calls
`step()` once per control step, which applies the queued keys, steps the
environment with the keyboard's action and records the step. ENTER keeps
the episode, BACKSPACE drops it, an episode that ends by itself is kept.
The next episode (seed + 1) starts with `next_episode()` or the next
`step()`, on the same compiled model (reset never recompiles). `write(path)` saves the kept episodes in
the demonstration format of `ikea_suite.datasets.hdf5`.
"""

import collections
from typing import Any

from ikea_suite.datasets import hdf5
from ikea_suite.datasets import recorder
from ikea_suite.teleop import keymap


class TeleopSession:
  """Keyboard-driven episodes of `env`, recorded.

  Args:
    env: an ikea_suite environment with the Cursor or a task_space arm.
    env_args: `hdf5.env_args(...)` that rebuild `env` (stored in the file).
    seed: seed of the first episode.
    hold_steps: control steps a motion key stays on (see keymap).
  """

  def __init__(self, env, env_args: dict[str, Any], seed: int = 0, hold_steps: int = 3):
    self._env, self._args = env, env_args
    self.command = keymap.KeyboardCommand(env.task.action_names, hold_steps=hold_steps)
    self._keys = collections.deque()
    self.episodes: list[recorder.Episode] = []
    self._seed = int(seed)
    self._ended = False
    self._start()

  def _start(self) -> None:
    self._env.random_state.seed(self._seed)
    self._timestep = self._env.reset()
    self.command.reset()
    self._recorder = recorder.EpisodeRecorder(self._env, self._seed)
    self._steps = 0

  def _end_episode(self, keep: bool) -> None:
    if keep and self._steps:
      self.episodes.append(self._recorder.finish())
    self._ended = True

  def next_episode(self) -> None:
    """Starts the next episode from the next seed (after an episode ended)."""
    self._seed += 1
    self._ended = False
    self._start()

  def on_key(self, keycode: int) -> None:
    """The viewer's key callback: queues the key (thread-safe) for the next `step`."""
    self._keys.append(int(keycode))

  def step(self) -> str | None:
    """One control step; returns "save", "discard" or "done" when the episode ended."""
    if self._ended:
      self.next_episode()
    while self._keys:
      event = self.command.press(self._keys.popleft())
      if event:
        self._keys.clear()
        self._end_episode(keep=event == "save")
        return event
    self._recorder.before_step(self._timestep.observation)
    action = self.command.action()
    self._timestep = self._env.step(action)
    moving = int(self._env.task.suggested_parts()[0])
    self._recorder.after_step(action, self._timestep, "teleop", moving)
    self._steps += 1
    if self._timestep.last():
      self._end_episode(keep=True)
      return "done"
    return None

  def write(self, path: str) -> int:
    """Writes the kept episodes to `path`; returns how many."""
    return hdf5.write(path, self.episodes, self._args,
                      action_names=list(self._env.task.action_names))
