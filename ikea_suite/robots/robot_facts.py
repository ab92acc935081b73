"""Reads the robot fact sheets (robots/facts/*.json) and writes MJCF bodies from them.

A fact sheet lists bodies in tree order with their frame in the parent,
inertial, joints, collision primitives and the bounds of each visual piece.
We turn that into MJCF with simple shapes: collision primitives as given, or
fitted to the link's mesh bounds where the sheet lists none (hidden, group 3),
and rounded shapes fitted to each sizeable visual piece (coloured MuJoCo
`supersphere` meshes, no contact or mass; see visual_shapes).
"""

import functools
import json
import pathlib

import numpy as np
from dm_control import mjcf

from ikea_suite import errors
from ikea_suite.robots import visual_shapes

FACTS_DIR = pathlib.Path(__file__).parent / "facts"
COLLISION_GROUP = 3
VISUAL_GROUP = 1


@functools.lru_cache(maxsize=None)
def load(name):
  path = FACTS_DIR / f"{name}.json"
  if not path.exists():
    valid = [p.stem for p in FACTS_DIR.glob("*.json")]
    raise errors.UnknownNameError("robot fact sheet", name, valid)
  return json.loads(path.read_text())


def actuator_limits(facts):
  """Joint name -> (low, high) of the sheet's motor or position control range."""
  return {a["joint"]: tuple(float(x) for x in a["ctrlrange"].split()) for a in facts["actuators"]}


def _float(value, default=0.0):
  return default if value is None else float(value)


def _fitted_collision_geoms(body, anchors):
  """Collision primitives for a link the sheet gives only as one whole-link mesh
  (the uncoloured entry's bounds): a cylinder round each joint housed, a capsule
  along each tube reaching from it, as visual_shapes fits them (the Panda's
  links are such drums and tubes). A box of the whole bounds would stand up to
  5 cm proud of the real link at its corners and drag parts it never touches.
  Shapes that are not round across (a block, a tube squashed into a thin box)
  stay boxes of their own bounds.
  """
  for piece in body.get("visual_mesh_bounds", []):
    if piece.get("rgba") is None:
      lo, hi = (np.asarray(b, dtype=float) for b in piece["bounds_in_body"])
      return [_primitive(shape) for shape in visual_shapes.fit(lo, hi, anchors)]
  return []


def _primitive(shape):
  """The MuJoCo primitive (as a fact-sheet collision entry) of a fitted shape."""
  half, axis = np.maximum(np.asarray(shape.half), 1e-3), shape.axis
  radius, length = half[[c for c in range(3) if c != axis]], half[axis]
  if shape.exponents == visual_shapes.BLOCK or not np.isclose(radius[0], radius[1]):
    return {"type": "box", "size": list(half), "pos": list(shape.centre)}
  kind = "cylinder" if shape.exponents == visual_shapes.DRUM else "capsule"
  # a capsule's size is its radius and the half length of its straight part
  length = length if kind == "cylinder" else max(length - radius[0], 1e-3)
  return {"type": kind, "size": [radius[0], length], "pos": list(shape.centre),
          "quat": list(visual_shapes.AXIS_QUATS[axis])}


def add_body(parent, body, name_prefix="", pos=None, quat=None, gravcomp=1.0, anchors=()):
  """Adds one fact-sheet body under MJCF element `parent`; returns the new body element.

  Geoms never contribute inertia (density 0): the sheet's inertial is the mass.
  `anchors` are the joints the body houses (visual_shapes.joint_anchors), which
  shape its visuals.
  """
  element = parent.add("body", name=name_prefix + body["name"],
                       pos=body["pos"] if pos is None else pos,
                       quat=body.get("quat", [1, 0, 0, 0]) if quat is None else quat,
                       gravcomp=gravcomp)
  inertial = body.get("inertial") or {}
  if inertial.get("mass"):
    element.add("inertial", mass=inertial["mass"], pos=inertial.get("pos", [0, 0, 0]),
                quat=inertial.get("quat", [1, 0, 0, 0]),
                diaginertia=np.maximum(inertial.get("diaginertia", [1e-6] * 3), 1e-8))
  for joint in body.get("joints", []):
    element.add("joint", name=name_prefix + joint["name"], type=joint.get("type", "hinge"),
                axis=joint["axis"], pos=joint.get("pos", [0, 0, 0]), range=joint["range"],
                limited=True, damping=_float(joint.get("damping")),
                armature=_float(joint.get("armature"), 0.01),
                frictionloss=_float(joint.get("frictionloss")))
  for k, geom in enumerate(body.get("collision_geoms") or _fitted_collision_geoms(body, anchors)):
    kwargs = dict(type=geom.get("type", "sphere"), size=geom["size"], density=0,
                  group=COLLISION_GROUP, rgba=(0.5, 0.5, 0.5, 0.3), contype=1, conaffinity=0)
    if "fromto" in geom:
      kwargs["fromto"] = geom["fromto"]
    else:
      kwargs["pos"] = geom.get("pos", [0, 0, 0])
      if "quat" in geom:
        kwargs["quat"] = geom["quat"]
    element.add("geom", name=f"{name_prefix}{body['name']}_col{k}", **kwargs)
  _add_visuals(element, body, name_prefix, anchors)
  for site in body.get("sites", []):
    element.add("site", name=name_prefix + site["name"], pos=site.get("pos", [0, 0, 0]),
                quat=site.get("quat", [1, 0, 0, 0]), size=[site["size"][0]], group=4,
                rgba=(0.9, 0.9, 0.1, 0.5))
  for camera in body.get("cameras", []):
    element.add("camera", name=name_prefix + camera["name"], pos=camera["pos"],
                quat=camera["quat"], fovy=_float(camera.get("fovy"), 60.0))
  return element


def _add_visuals(element, body, name_prefix, anchors):
  """Rounded shapes for the visual pieces, each a MuJoCo `supersphere` mesh of its own
  size; drawn only: no contact and no mass."""
  for k, (shape, rgba) in enumerate(visual_shapes.shapes(body, anchors)):
    name = f"{name_prefix}{body['name']}_vis{k}"
    element.root.asset.add("mesh", name=name, builtin="supersphere", scale=shape.mesh_scale,
                           params=(visual_shapes.RESOLUTION, *shape.exponents))
    element.add("geom", name=name, type="mesh", mesh=name, pos=shape.centre, quat=shape.quat,
                rgba=rgba, density=0, contype=0, conaffinity=0, group=VISUAL_GROUP)


def add_tree(parent, facts, root=None, name_prefix="", skip=(), gravcomp=1.0, pos=None,
             quat=None):
  """Adds the subtree of `root` (default: the sheet's root) under `parent`.

  `skip` names bodies left out with their subtrees. `pos` and `quat`
  override the root body's own frame. Returns {fact body name: element}.
  """
  bodies = facts["bodies"]
  root = root or bodies[0]["name"]
  anchors = visual_shapes.joint_anchors(bodies)
  elements = {}
  for body in bodies:
    name = body["name"]
    if name in skip or (name != root and body["parent"] not in elements):
      continue
    if name == root:
      elements[name] = add_body(parent, body, name_prefix, pos=pos, quat=quat, gravcomp=gravcomp,
                                anchors=anchors[name])
    else:
      elements[name] = add_body(elements[body["parent"]], body, name_prefix, gravcomp=gravcomp,
                                anchors=anchors[name])
  return elements


def build_model(name, robot, root, **tree_options):
  """(mjcf root, elements by body name, actuator limits) of a robot from its fact sheet."""
  facts = load(robot)
  model = mjcf.RootElement(model=name)
  model.compiler.angle = "radian"   # the fact sheets are in radians
  elements = add_tree(model.worldbody, facts, skip=("base",), root=root, **tree_options)
  return model, elements, actuator_limits(facts)
