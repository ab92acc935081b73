"""Arm visuals: rounded shapes fitted to the fact sheets, drawn only, never felt."""

import mujoco
import numpy as np
import pytest
from dm_control import mjcf

from ikea_suite.robots import registry
from ikea_suite.robots import robot_facts
from ikea_suite.robots import visual_shapes

SHEET_ARMS = ("sawyer", "baxter", "panda")   # built from fact sheets
SHEETS = ("sawyer", "baxter", "panda", "panda_gripper", "rethink_gripper")


def _physics(robot, strip_visuals=False):
  entity = registry.get(robot).factory()
  if strip_visuals:
    for geom in entity.mjcf_model.find_all("geom"):
      if geom.group == robot_facts.VISUAL_GROUP:
        geom.remove()
    for mesh in entity.mjcf_model.find_all("mesh"):
      mesh.remove()
  return mjcf.Physics.from_mjcf_model(entity.mjcf_model)


def _colliding(model):
  return [i for i in range(model.ngeom) if model.geom_contype[i] or model.geom_conaffinity[i]]


@pytest.mark.parametrize("robot", SHEET_ARMS)
def test_visual_geoms_are_rounded_meshes_that_never_collide(robot):
  model = _physics(robot).model
  visual = np.flatnonzero(model.geom_group == robot_facts.VISUAL_GROUP)
  assert len(visual) > 20
  assert np.all(model.geom_contype[visual] == 0) and np.all(model.geom_conaffinity[visual] == 0)
  assert np.all(model.geom_type[visual] == mujoco.mjtGeom.mjGEOM_MESH)   # supersphere meshes


@pytest.mark.parametrize("robot", SHEET_ARMS + ("jaco",))
def test_no_arm_is_drawn_with_boxes(robot):
  model = _physics(robot).model
  drawn = model.geom_group <= 2   # the groups MuJoCo draws by default
  assert np.sum(drawn) > 10 and not np.any(model.geom_type[drawn] == mujoco.mjtGeom.mjGEOM_BOX)


@pytest.mark.parametrize("robot", SHEET_ARMS)
def test_visuals_leave_the_physics_unchanged(robot):
  with_visuals, without = _physics(robot).model, _physics(robot, strip_visuals=True).model
  for field in ("body_mass", "body_inertia", "body_ipos", "body_iquat", "body_pos", "body_quat"):
    np.testing.assert_array_equal(getattr(with_visuals, field), getattr(without, field), field)
  a, b = _colliding(with_visuals), _colliding(without)
  assert [with_visuals.id2name(i, "geom") for i in a] == [without.id2name(i, "geom") for i in b]
  for field in ("geom_type", "geom_size", "geom_pos", "geom_quat", "geom_friction",
                "geom_condim", "geom_contype", "geom_conaffinity", "geom_margin"):
    np.testing.assert_array_equal(getattr(with_visuals, field)[a], getattr(without, field)[b], field)


def _body_frame_bounds(model, geom):
  """Bounds of a mesh geom's vertices in its body's frame."""
  mesh = model.geom_dataid[geom]
  start, count = model.mesh_vertadr[mesh], model.mesh_vertnum[mesh]
  rotation = np.zeros(9)
  mujoco.mju_quat2Mat(rotation, model.geom_quat[geom])
  points = model.geom_pos[geom] + model.mesh_vert[start:start + count] @ rotation.reshape(3, 3).T
  return points.min(axis=0), points.max(axis=0)


@pytest.mark.parametrize("robot,sheet", [("sawyer", "sawyer"), ("panda", "panda")])
def test_drawn_meshes_fill_the_fitted_shapes(robot, sheet):
  model = _physics(robot).model
  facts = robot_facts.load(sheet)
  anchors = visual_shapes.joint_anchors(facts["bodies"])
  checked = 0
  for body in facts["bodies"]:
    for k, (shape, _) in enumerate(visual_shapes.shapes(body, anchors[body["name"]])):
      lo, hi = _body_frame_bounds(model, model.geom(f"{body['name']}_vis{k}").id)
      centre, half = np.array(shape.centre), np.array(shape.half)
      np.testing.assert_allclose(lo, centre - half, atol=2e-4)
      np.testing.assert_allclose(hi, centre + half, atol=2e-4)
      checked += 1
  assert checked > 20


@pytest.mark.parametrize("sheet", SHEETS)
def test_shapes_stay_inside_their_pieces(sheet):
  facts = robot_facts.load(sheet)
  anchors = visual_shapes.joint_anchors(facts["bodies"])
  for body in facts["bodies"]:
    boxes = visual_shapes.collision_boxes(body.get("collision_geoms") or [])
    slack = 0.01 if boxes else 1e-9   # a finger is drawn as its collision boxes, 1 cm leeway
    for lo, hi, _ in visual_shapes.pieces(body):
      for shape in visual_shapes.fit(lo, hi, anchors[body["name"]], boxes):
        centre, half = np.array(shape.centre), np.array(shape.half)
        assert np.all(half > 0)
        assert np.all(centre - half >= lo - slack) and np.all(centre + half <= hi + slack), body


def test_panda_link_is_a_housing_round_its_joint_and_a_tube():
  # panda.json: link1's piece spans x +-0.055, y -0.129..0.055, z -0.1915..0.0555;
  # joint1 (its own, about z) and joint2 (link2's, about y) sit at its origin.
  link1 = next(b for b in robot_facts.load("panda")["bodies"] if b["name"] == "link1")
  anchors = visual_shapes.joint_anchors(robot_facts.load("panda")["bodies"])["link1"]
  assert [(tuple(p), axis) for p, axis in anchors] == [((0, 0, 0), 2), ((0, 0, 0), 1)]
  (lo, hi, _), = visual_shapes.pieces(link1)
  drum, tube = visual_shapes.fit(lo, hi, anchors)
  assert drum.exponents == visual_shapes.DRUM and drum.axis == 2
  np.testing.assert_allclose(drum.centre[:2], (0, 0), atol=1e-3)   # on joint1's axis
  np.testing.assert_allclose(drum.half[:2], (0.055, 0.055), atol=1e-3)
  assert tube.exponents == visual_shapes.TUBE and tube.axis == 1   # reaching out along -y
  assert tube.centre[1] - tube.half[1] == pytest.approx(lo[1])


def test_a_shell_listed_in_two_colours_is_drawn_once_in_the_livery():
  # sawyer.json: right_l2 lists a white and a red piece of equal bounds (0.106 x 0.106 x 0.31).
  l2 = next(b for b in robot_facts.load("sawyer")["bodies"] if b["name"] == "right_l2")
  colours = [tuple(rgba[:3]) for _, _, rgba in visual_shapes.pieces(l2)]
  assert (1.0, 0.0, 0.0) in colours and (1.0, 1.0, 1.0) not in colours


def test_a_finger_is_drawn_as_its_collision_boxes():
  finger = next(b for b in robot_facts.load("rethink_gripper")["bodies"] if b["name"] == "l_finger")
  drawn = [shape for shape, _ in visual_shapes.shapes(finger)]
  boxes = visual_shapes.collision_boxes(finger["collision_geoms"])
  assert len(drawn) == len(boxes) == 2
  for shape, (lo, hi) in zip(drawn, sorted(boxes, key=lambda b: -np.prod(b[1] - b[0]))):
    np.testing.assert_allclose(shape.centre, (lo + hi) / 2)
    np.testing.assert_allclose(shape.half, (hi - lo) / 2)


def _collision_bounds(model, geom):
  """Bounds of a primitive collision geom in its body's frame (from its local AABB)."""
  centre, half = model.geom_aabb[geom, :3], model.geom_aabb[geom, 3:]
  corners = centre + half * np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)])
  rotation = np.zeros(9)
  mujoco.mju_quat2Mat(rotation, model.geom_quat[geom])
  points = model.geom_pos[geom] + corners @ rotation.reshape(3, 3).T
  return points.min(axis=0), points.max(axis=0)


def test_panda_links_collide_as_drums_and_tubes_inside_their_mesh_bounds():
  # The Panda's sheet gives no collision primitives, only each link's whole-mesh
  # bounds; a box of those bounds stood up to 5 cm proud of the link at its corners.
  model = _physics("panda").model
  for body in robot_facts.load("panda")["bodies"]:
    if not body["name"].startswith("link") or body["name"] == "link0":
      continue
    whole = next(p for p in body["visual_mesh_bounds"] if p.get("rgba") is None)
    lo, hi = (np.asarray(b) for b in whole["bounds_in_body"])
    geoms = [i for i in range(model.ngeom)
             if model.id2name(i, "geom").startswith(f"{body['name']}_col")]
    types = {int(model.geom_type[i]) for i in geoms}
    assert int(mujoco.mjtGeom.mjGEOM_CYLINDER) in types, body["name"]
    assert int(mujoco.mjtGeom.mjGEOM_CAPSULE) in types or body["name"] == "link7", body["name"]
    for i in geoms:
      glo, ghi = _collision_bounds(model, i)
      assert np.all(glo >= lo - 1e-3) and np.all(ghi <= hi + 1e-3), model.id2name(i, "geom")
