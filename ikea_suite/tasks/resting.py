"""Resting poses: every loose part starts an episode at rest on its resting face.

A part is laid with its thinnest extent vertical (placement.resting_rotation; an arm's
root part may be turned over or across; a panel stands in the rack), its lowest corner
LANDING above the support, and it lands within the first control step. Some parts are
not at rest laid that way:

- a pedestal's heavy foot and long column tip it onto its side; a drawer whose front
  reaches below its bottom rocks onto that edge; a bed rail turns onto its ledge;
- a tall thin panel stood upright in its rack slot leans into the slot, then creeps
  until its foot meets the other fin (for 20 s, a dresser's back at half scale);
- a part lying on a cylinder's flat end lands badly at some yaws: MuJoCo's
  plane-cylinder contact drops out for part of the way as the landing presses the end
  into the floor (a stool's round seat fell 5 mm through at 4% of yaws, and sprang back
  for 0.3 s).

Such a part starts instead in the pose it comes to rest in, found by simulating it alone,
once per model (cached): on a plane, or standing in its rack, with the task's physics
configuration (physics_settings: the parts' contacts and the support's hard ones).
Nothing in the physics changes, only where a part starts. A work table's top, a box,
rests parts as the plane does (physics_settings.BOX_SUPPORT_CCD_TOLERANCE), so the
poses found on the plane hold there too.

A part is not at rest where, after landing (LANDED_AFTER), it moves more than REST_DRIFT
or turns more than REST_TURN in the next CHECK_TIME, or where it landed on a cylinder's
flat end (its axis within FLAT_END of vertical). Every other part keeps its placement
exactly (the same pose and landing, so its episodes are unchanged). A found pose passes
the same check, without the landing, before it is used.
"""

import dataclasses
import logging
import os
import pathlib
import xml.etree.ElementTree as ET

import mujoco
import numpy as np

from ikea_suite import geometry
from ikea_suite import physics_settings
from ikea_suite.props import model_format

LANDING = 1e-3         # m a laid part's lowest corner starts above its support
LANDED_AFTER = 0.05    # s: a part has landed within one control step (20 Hz)
CHECK_TIME = 2.0       # s over which a landed part must stay at rest
# Half of what tests/test_rest.py allows (2 mm, 1 degree): the scene is not the plane.
REST_DRIFT = 1e-3      # m
REST_TURN = np.radians(0.5)
# Settling: simulated a second at a time until no unsettled part moves more than
# SETTLED_DRIFT or turns more than SETTLED_TURN in one, for at most SETTLE_TIME.
SETTLED_DRIFT = 2e-5   # m per second
SETTLED_TURN = np.radians(0.005)
SETTLE_TIME = 60.0     # s
FLAT_END = np.radians(1.0)
_ROUNDS = 3            # settle-and-check rounds before giving up on a part
_SPACING = 0.5         # m of air between parts simulated side by side


@dataclasses.dataclass(frozen=True)
class Rest:
  """Where a part starts, relative to its support.

  rotation: part to world (3, 3), up to a turn about the vertical.
  position: the part origin (3,) at rest, its height above the support (z) and, in a
    rack, its place in the rack frame; None where the part is laid as usual (its lowest
    corner LANDING above the support) and lands at rest.
  """
  rotation: np.ndarray
  position: np.ndarray | None = None


def laid_height(bounds, rotation):
  """Height (m) above the support of the origin of a part laid at `rotation` (3, 3), its
  collision bounds' lowest corner LANDING above the support."""
  return -(geometry.box_corners(*bounds) @ rotation.T)[:, 2].min() + LANDING


def rests_on_support(spec, rotations):
  """The Rest of each part lying on a flat support, laid at its rotation.

  Args:
    spec: the FurnitureSpec.
    rotations: part index -> rotation (3, 3) it is laid at.
  Returns:
    part index -> Rest (rotation as given and position None where laid that way it
    lands at rest; else the pose it rests in, position (0, 0, height)).
  """
  key = tuple(sorted((int(i), np.asarray(r, dtype=float).tobytes()) for i, r in rotations.items()))
  return dict(_cached(_rests_on_support, spec, key))


def _rests_on_support(spec, key):
  # Parts alike in shape, mass and rotation rest alike: one of each is simulated.
  first = {}
  for i, rot in key:
    first.setdefault((_shape(spec, i), rot), i)
  simulated = sorted(set(first.values()))
  rotations = dict(key)
  x, poses = 0.0, []
  for i in simulated:   # side by side along x, clear of each other
    rot = np.frombuffer(rotations[i]).reshape(3, 3)
    reach = np.linalg.norm(spec.parts[i].bounds, axis=1).max()
    x += reach
    poses.append((rot, np.array([x, 0.0, laid_height(spec.parts[i].bounds, rot)])))
    x += reach + _SPACING
  found = dict(zip(simulated, _settle(spec, simulated, poses, _plane())))
  out = []
  for i, rot in key:
    pose = found[first[(_shape(spec, i), rot)]]
    out.append((i, Rest(np.frombuffer(rot).reshape(3, 3)) if pose is None else
                Rest(pose[0], np.array([0.0, 0.0, pose[1][2]]))))
  return tuple(out)


# (function, the spec's file, when it was written, its scale, key) -> result: a spec read
# again, or scaled again to the same size, has the same numbers, so it rests alike.
_CACHE = {}
_CACHE_SIZE = 512


def _cached(compute, spec, key):
  """compute(spec, key), once per furniture file, scale and key."""
  try:
    written = os.stat(spec.path).st_mtime_ns
  except OSError:
    written = None
  entry = (compute.__name__, spec.path, written, spec.scale, key)
  if entry not in _CACHE:
    if len(_CACHE) >= _CACHE_SIZE:
      _CACHE.pop(next(iter(_CACHE)))
    _CACHE[entry] = compute(spec, key)
  return _CACHE[entry]


def _shape(spec, index):
  """A part's collision and mass description without its names (equal for parts alike)."""
  body = ET.Element("body")
  for child in spec.parts[index].element:
    element = ET.fromstring(ET.tostring(child))
    for node in element.iter():
      node.attrib.pop("name", None)
    body.append(element)
  return ET.tostring(body)


def rests_in_rack(spec, rack_geoms, panels, lean):
  """How each panel standing in a rack at the origin starts: upright, or leaning.

  Upright in the middle of its slot is a rest only where the panel rises back upright
  from leaning half as far as the slot lets it (`lean`), either way about the slot's
  length (the rack's y axis): a tall thin panel balances upright in a simulation whose
  rack is square to the axes, yet leans over in a scene. (Leaning the whole way,
  it would start touching a fin, and a panel that would rise back stays wedged.) Where
  it does not rise back, it starts as it comes to rest leaning from there, towards +x or
  towards -x; a panel that stands in its slot turned half a turn takes the rest towards
  -x, turned, so that every panel in the rack leans the same way and none leans onto
  its neighbour.

  Args:
    spec: the FurnitureSpec.
    rack_geoms: [(position (3,), half sizes (3,), quaternion (4,))] of the rack's boxes,
      rack frame.
    panels: [(part index, rotation (3, 3), position (3,))] where each panel is stood,
      upright in the middle of its slot, its lowest corner LANDING above the plate (rack
      frame; its thickness along x).
    lean: rad, how far a panel leans in its slot before it meets a fin.
  Returns:
    Per panel, (Rest towards +x, Rest towards -x), rack frame: position None (both)
    where the panel stands upright as stood.
  """
  key = (tuple(tuple(tuple(np.round(v, 12)) for v in box) for box in rack_geoms),
         tuple((int(i), np.asarray(r, dtype=float).tobytes(), np.asarray(p, dtype=float).tobytes())
               for i, r, p in panels), float(lean))
  return list(_cached(_rests_in_rack, spec, key))


def _rests_in_rack(spec, key):
  boxes, panels, lean = key
  supports = _plane() + [ET.Element("geom", type="box", pos=_text(p), size=_text(s),
                                    quat=_text(q)) for p, s, q in boxes]
  upright = [(np.frombuffer(r).reshape(3, 3), np.frombuffer(p)) for _, r, p in panels]
  # Panels alike stand in slots alike (a slot is cut to its panel): one of each is
  # simulated, and the others rest as it does, moved to their own slot.
  first = {}
  for k, (i, r, _) in enumerate(panels):
    first.setdefault((_shape(spec, i), r), k)
  simulated = sorted(set(first.values()))
  leaning = {}
  for sign in (1.0, -1.0):
    tilted = [_leaning(spec.parts[panels[k][0]].bounds, *upright[k], sign * lean / 2)
              for k in simulated]
    settled = _settle(spec, [panels[k][0] for k in simulated], tilted, supports)
    for k, start, found in zip(simulated, tilted, settled):
      rot, pos = start if found is None else found
      if np.linalg.norm(geometry.mat_to_axis_angle(rot @ upright[k][0].T)) > REST_TURN:
        leaning[k, sign] = (rot, pos)
  out = []
  for k, (i, r, _) in enumerate(panels):
    like = first[(_shape(spec, i), r)]
    shift = upright[k][1] - upright[like][1]
    plus, minus = ((leaning[like, sign][0], leaning[like, sign][1] + shift)
                   if (like, sign) in leaning else None for sign in (1.0, -1.0))
    if plus is None and minus is None:   # it rises back upright either way
      out.append((Rest(upright[k][0]), Rest(upright[k][0])))
    else:
      out.append((Rest(*(plus or minus)), Rest(*(minus or plus))))
  return tuple(out)


def _leaning(bounds, rot, pos, angle):
  """The pose (rotation, position) of a part standing upright at (rot, pos) turned by
  `angle` about the rack's y axis through the middle of its bottom face, raised so that
  its lowest corner stays as high as it was."""
  corners = geometry.box_corners(*bounds) @ rot.T + pos
  pivot = corners[np.argsort(corners[:, 2], kind="stable")[:4]].mean(axis=0)
  turn = geometry.axis_angle_to_mat([0.0, angle, 0.0])
  turned, moved = turn @ rot, pivot + turn @ (pos - pivot)
  lowest = (geometry.box_corners(*bounds) @ turned.T + moved)[:, 2].min()
  return turned, moved + [0.0, 0.0, corners[:, 2].min() - lowest]


def _text(values):
  return " ".join(repr(float(v)) for v in values)


def _plane():
  return [ET.Element("geom", type="plane", size="0 0 1")]


def _absolute_dirs(compiler, model_dir):
  """Asset folders made absolute (the model is compiled from a string, not its file)."""
  for name in ("meshdir", "texturedir", "assetdir"):
    if compiler.get(name) is not None and not os.path.isabs(compiler.get(name)):
      compiler.set(name, str((model_dir / compiler.get(name)).resolve()))
  if compiler.get("meshdir") is None and compiler.get("assetdir") is None:
    compiler.set("meshdir", str(model_dir.resolve()))


def _model(spec, indices, supports):
  """A plain MjModel of the parts `indices` (their bodies in that order) on `supports`
  (static geoms, configured as the task configures supports), materials left out."""
  root = model_format.parts_xml(spec)
  compiler = root.find("compiler")
  if compiler is None:
    compiler = ET.SubElement(root, "compiler")
  _absolute_dirs(compiler, pathlib.Path(spec.path).parent)
  assets = root.find("asset")
  for element in list(assets):
    if element.tag in ("material", "texture"):
      assets.remove(element)
  world = root.find("worldbody")
  bodies = list(world)
  for body in bodies:
    world.remove(body)
  for geom in supports:
    world.append(geom)
  for i in indices:
    world.append(bodies[i])
  for element in world.iter():
    element.attrib.pop("material", None)
  model = mujoco.MjModel.from_xml_string(ET.tostring(root, encoding="unicode"))
  physics_settings.configure_model(model)
  physics_settings.configure_supports(model, np.arange(len(supports)))
  return model


def _settle(spec, indices, poses, supports):
  """For each (rotation, position) of `poses` (parts `indices`), None where the part
  started there stays at rest, else the (rotation, position) it comes to rest in."""
  model = _model(spec, indices, supports)
  data = mujoco.MjData(model)
  bodies = np.arange(1, len(indices) + 1)
  dt = model.opt.timestep
  landing, check, second = (int(round(t / dt)) for t in (LANDED_AFTER, CHECK_TIME, 1.0))

  def pose():
    return data.xpos[bodies].copy(), data.xmat[bodies].reshape(-1, 3, 3).copy()

  def motion(before, after):
    drift = np.linalg.norm(after[0] - before[0], axis=1)
    turn = np.array([np.linalg.norm(geometry.mat_to_axis_angle(b @ a.T))
                     for a, b in zip(before[1], after[1])])
    return drift, turn

  def on_flat_end():
    """Whether each body touches a support with a cylinder whose axis is near vertical."""
    out = np.zeros(len(indices), dtype=bool)
    for contact in data.contact[:data.ncon]:
      for geom, other in ((contact.geom1, contact.geom2), (contact.geom2, contact.geom1)):
        if (model.geom_bodyid[other] == 0 and model.geom_bodyid[geom] > 0
            and model.geom_type[geom] == mujoco.mjtGeom.mjGEOM_CYLINDER
            and abs(data.geom_xmat[geom, 8]) > np.cos(FLAT_END)):
          out[model.geom_bodyid[geom] - 1] = True
    return out

  found = [None] * len(indices)
  start = list(poses)
  for _ in range(_ROUNDS):
    mujoco.mj_resetData(model, data)
    for k, (rot, pos) in enumerate(start):
      data.qpos[7 * k:7 * k + 3] = pos
      data.qpos[7 * k + 3:7 * k + 7] = geometry.mat_to_quat(rot)
    mujoco.mj_forward(model, data)
    mujoco.mj_step(model, data, landing)
    landed = pose()
    mujoco.mj_step(model, data, check)
    drift, turn = motion(landed, pose())
    laid = np.array([f is None for f in found])   # landed from LANDING, not placed at rest
    moving = (drift > REST_DRIFT) | (turn > REST_TURN) | (laid & on_flat_end())
    if not moving.any():
      return found
    for _ in range(int(SETTLE_TIME)):
      before = pose()
      mujoco.mj_step(model, data, second)
      drift, turn = motion(before, pose())
      if not ((drift > SETTLED_DRIFT) | (turn > SETTLED_TURN))[moving].any():
        break
    pos, rot = pose()
    for k in np.flatnonzero(moving):
      found[k] = start[k] = (rot[k], pos[k])
  names = [spec.parts[indices[k]].name for k in np.flatnonzero(moving)]
  logging.warning("%s: %s still moved after %d rounds of settling for %g s; they start where "
                  "the last round left them", spec.name, names, _ROUNDS, SETTLE_TIME)
  return found


@dataclasses.dataclass(frozen=True)
class StartMotion:
  """How far the parts moved with zero actions from the end of an episode's first step."""
  drift: float     # m, the largest displacement of any part's origin
  turn: float      # rad, the largest rotation of any part
  worst_part: str  # the part that moved most (drift over 2 mm and turn over 1 degree, weighed)


def start_motion(env, seconds=CHECK_TIME):
  """Resets `env`, steps it once with zero actions, then for `seconds` more, and measures
  how far the parts moved in those seconds (a diagnostic of the start being at rest).

  Args:
    env: an ikea_suite environment.
    seconds: simulated time after the first step.
  Returns:
    A StartMotion.
  """
  env.reset()
  zero = np.zeros(env.action_spec().shape)
  env.step(zero)
  furniture = env.task.furniture
  pos0, rot0 = (np.array(x) for x in furniture.part_poses(env.physics))
  for _ in range(int(round(seconds / env.control_timestep()))):
    env.step(zero)
  pos, rot = furniture.part_poses(env.physics)
  drift = np.linalg.norm(pos - pos0, axis=1)
  turn = np.array([np.linalg.norm(geometry.mat_to_axis_angle(r @ r0.T)) for r, r0 in zip(rot, rot0)])
  worst = int(np.argmax(np.maximum(drift / 0.002, turn / np.radians(1.0))))
  return StartMotion(float(drift.max()), float(turn.max()), furniture.spec.parts[worst].name)
