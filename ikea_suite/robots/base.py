"""What an assembly task needs from an agent, whatever its body."""

import abc
from typing import NamedTuple

import numpy as np
from dm_control import composer


class ReachZone(NamedTuple):
  """Where a fixed-base robot needs its parts (tasks/arm_placement.py places them)."""
  base_xy: np.ndarray     # (2,) world position of the base
  base_rot: np.ndarray    # (3, 3) world rotation of the base
  reach: float            # metres from the base that parts may lie at
  sector: float           # half-angle (rad) either side of the base's heading
  min_distance: float     # metres from the base inside which no part's centre lies
  root_distance: float    # metres from the base to the centre of the part built onto
  arms: int = 1           # two: loose parts alternate between the arms' halves (Baxter)
  # (bearing, metres): beyond that bearing from the heading parts may lie out to that
  # distance instead of `reach`; None: `reach` at every bearing.
  side_reach: tuple = None
  # The robot standing at its home pose, seen from above: an (n, 5) array, one row per
  # collision geom, (x low, y low, x high, y high) corners (m) of its box in the base frame
  # and the world z (m) of its lowest point. Parts and the panel rack keep clear of each
  # box whose lowest point lies less than the placement's gap above their top (a torso
  # wider than min_distance leaves room for; an arm hanging at home over a standing
  # panel); None: none.
  home_footprint: np.ndarray = None


class Robot(composer.Entity, abc.ABC):
  """An agent entity: a named action vector it applies once per control step.

  The task appends one `connect` entry after the robot's own actions, so a
  robot never sees it.
  """

  # The dataclass of the load() options this robot takes (config.CursorConfig,
  # config.ArmConfig's subclass for an arm): their only defaults and checks, and its
  # WORK_SCALE, the furniture scale it loads at when load() gets none.
  CONFIG = None

  @property
  def config(self):
    """The robot's options, as built (an instance of its CONFIG)."""
    return self._config

  def max_physics_timestep(self, physics):
    """The largest physics time step this robot's actuators take in `physics` (compiled).

    Returns:
      (seconds, why): infinite and "" for a robot without servos (the Cursor).
    """
    return float("inf"), ""

  @property
  @abc.abstractmethod
  def action_names(self):
    """Names of the robot's action entries, each in [-1, 1]."""

  def mount(self, arena):
    """Attaches the robot to the arena at its base pose; returns the attachment frame."""
    return arena.attach(self)

  def bind_scene(self, arena, furniture, assembly, control_timestep):
    """Called once at build time, after the furniture is attached; may add elements."""

  @abc.abstractmethod
  def apply_action(self, physics, action, random_state):
    """Applies the robot's slice of a (clipped, finite) action."""

  def on_parts_moved(self, physics, part_indices):
    """Called after the task snapped parts to new poses during a connection."""

  @property
  def control_mode(self):
    """How actions drive the robot (a robots.control_modes name), or None for a robot with
    one fixed action layout (the Cursor)."""
    return None

  @property
  def reach_zone(self):
    """The ReachZone within which a fixed-base robot needs its parts, or None for a robot
    that reaches everywhere (the Cursor); the task places parts by it."""
    return None

  @property
  def cameras(self):
    """Named cameras the robot carries (name -> MJCF camera), for load(cameras=...)."""
    return {}

  @abc.abstractmethod
  def tool_positions(self, physics):
    """(tools, 3) world positions of the robot's tools (cursors or tool-centre points)."""

  @abc.abstractmethod
  def held_parts_by_tool(self, physics, part_body_ids):
    """(tools, parts) bool: the parts (bodies `part_body_ids`) each tool holds directly."""
