"""Key presses -> the action vector of a Cursor or a task-space arm.

MuJoCo's viewer reports key presses only (held keys repeat; no releases),
so a motion key drives its axis at full speed for `hold_steps` control
steps after each press or repeat: holding a key moves steadily, a tap
nudges. Keys are GLFW key codes, as the viewer's `key_callback` gets them
(letters are their upper-case ASCII codes).

| key | effect |
|---|---|
| W / S | move +x / -x |
| A / D | move +y / -y |
| R / F | move +z / -z |
| I / K | rotate about +x / -x |
| J / L | rotate about +y / -y |
| U / O | rotate about +z / -z |
| G | toggle the gripper (arms: close/open) or select (Cursor: hold/release) |
| C | connect (on for one control step) |
| TAB | switch the controlled cursor or arm |
| ENTER | keep the episode and start the next |
| BACKSPACE | discard the episode and start again |
"""

import numpy as np

from ikea_suite import errors

PER_AGENT = 7   # move x y z, rotate x y z, gripper/select: the Cursor's and task_space arms' layout
KEY_TAB, KEY_ENTER, KEY_BACKSPACE = 258, 257, 259
MOTION_KEYS = {
    ord("W"): (0, 1.0), ord("S"): (0, -1.0), ord("A"): (1, 1.0), ord("D"): (1, -1.0),
    ord("R"): (2, 1.0), ord("F"): (2, -1.0), ord("I"): (3, 1.0), ord("K"): (3, -1.0),
    ord("J"): (4, 1.0), ord("L"): (4, -1.0), ord("U"): (5, 1.0), ord("O"): (5, -1.0),
}
GRIP_KEY, CONNECT_KEY = ord("G"), ord("C")
EVENTS = {KEY_ENTER: "save", KEY_BACKSPACE: "discard"}
TASK_SPACE_LAYOUT = ("move_x", "move_y", "move_z", "rotate_x", "rotate_y", "rotate_z")


def check_layout(action_names: list[str]) -> int:
  """Number of agents (cursors or arms) of an action layout the keyboard can drive.

  Raises:
    OptionValueError: the layout is not 7 task-space entries per agent plus `connect`
      (an arm in a joint or absolute-pose control mode).
  """
  body = action_names[:-1]
  agents = len(body) // PER_AGENT
  ok = (action_names[-1:] == ["connect"] and agents and len(body) == agents * PER_AGENT
        and all(body[a * PER_AGENT + i].endswith(entry) for a in range(agents)
                for i, entry in enumerate(TASK_SPACE_LAYOUT)))
  if not ok:
    raise errors.OptionValueError(
        "keyboard teleoperation drives the Cursor or an arm with control_mode 'task_space' or "
        f"'impedance'; got actions {', '.join(action_names)}")
  return agents


class KeyboardCommand:
  """Holds the keyboard's command and turns it into one action per control step.

  Args:
    action_names: the task's action names (`env.task.action_names`).
    hold_steps: control steps a motion key stays on after a press or repeat.
    speed: action magnitude of a motion key, in (0, 1].
  """

  def __init__(self, action_names: list[str], hold_steps: int = 3, speed: float = 1.0):
    self.num_agents = check_layout(list(action_names))
    self._size = len(action_names)
    self._hold_steps, self._speed = int(hold_steps), float(speed)
    self.reset()

  def reset(self) -> None:
    """Everything off: no motion, grippers open (selects off), agent 0 active."""
    self.agent = 0
    self._timers = np.zeros((self.num_agents, 6), dtype=int)
    self._signs = np.zeros((self.num_agents, 6))
    self.grip = np.full(self.num_agents, -1.0)
    self._connect = False

  def press(self, keycode: int) -> str | None:
    """Applies one key press; returns "save" or "discard" for episode keys, else None."""
    if keycode in MOTION_KEYS:
      axis, sign = MOTION_KEYS[keycode]
      self._timers[self.agent, axis] = self._hold_steps
      self._signs[self.agent, axis] = sign
    elif keycode == GRIP_KEY:
      self.grip[self.agent] = -self.grip[self.agent]
    elif keycode == CONNECT_KEY:
      self._connect = True
    elif keycode == KEY_TAB:
      self.agent = (self.agent + 1) % self.num_agents
    return EVENTS.get(keycode)

  def action(self) -> np.ndarray:
    """The action for this control step; motion timers and the connect pulse count down."""
    action = np.zeros(self._size)
    for a in range(self.num_agents):
      on = self._timers[a] > 0
      action[a * PER_AGENT:a * PER_AGENT + 6] = np.where(on, self._signs[a] * self._speed, 0.0)
      action[a * PER_AGENT + 6] = self.grip[a]
    action[-1] = 1.0 if self._connect else -1.0
    self._timers = np.maximum(self._timers - 1, 0)
    self._connect = False
    return action
