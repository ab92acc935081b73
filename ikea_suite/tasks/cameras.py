"""Rendering for image observations: RGB, depth and part segmentation in few GL passes.

The kinds are config.IMAGE_KINDS. Segmentation pixels hold labels, not MuJoCo ids: part k of the furniture is
k (0..n-1), and the rest of the scene uses the negative ids below.
"""

import os

import mujoco
import numpy as np
from dm_control.mujoco import engine

from ikea_suite import errors

BACKGROUND_ID = -1   # sky, backdrop walls, anything that is not floor, robot or a part
FLOOR_ID = -2        # the arena's floor plane
ROBOT_ID = -3        # every geom of the robot entity (and entities attached to it)


# The process in which the suite first rendered. A process forked from it inherits the GL
# driver's state without the driver's threads, and the first context it makes then waits
# forever (EGL and OSMesa with Mesa's llvmpipe, seen with gymnasium's AsyncVectorEnv).
_GL_PROCESS = None


def claim_gl() -> None:
  """Call before making an OpenGL context: records this process as one that renders.

  Raises:
    RenderAfterForkError: this process was forked from one that had rendered already.
  """
  global _GL_PROCESS
  pid = os.getpid()
  if _GL_PROCESS is not None and _GL_PROCESS != pid:
    raise errors.RenderAfterForkError(
        f"this process (pid {pid}) was forked after process {_GL_PROCESS} rendered, and "
        f"OpenGL cannot render in it: start vector env workers with the 'spawn' or "
        f"'forkserver' start method (gymnasium.make_vec(..., vectorization_mode='async', "
        f"vector_kwargs={{'context': 'forkserver'}})), or fork before rendering")
  _GL_PROCESS = pid


def segmentation_labels(physics, furniture, robot, floor):
  """Label of each geom id, shifted by one: index 0 is for pixels that show no geom."""
  model = physics.model
  labels = np.full(model.ngeom + 1, BACKGROUND_ID, dtype=np.int32)
  labels[physics.bind(floor).element_id + 1] = FLOOR_ID
  robot_geoms = robot.mjcf_model.find_all("geom")
  if robot_geoms:
    labels[np.atleast_1d(physics.bind(robot_geoms).element_id) + 1] = ROBOT_ID
  part_of_body = np.full(model.nbody, -1)
  part_of_body[furniture.body_ids] = np.arange(len(furniture.body_ids))
  geom_part = part_of_body[model.geom_bodyid]
  is_part = geom_part >= 0
  labels[1:][is_part] = geom_part[is_part]
  return labels


class MultiKindCamera(engine.Camera):
  """A dm_control camera that renders any subset of RGB, depth and segmentation.

  dm_control's `Camera.render` renders the scene once per kind. Here the scene
  is updated once, RGB and depth are read from a single pass, and segmentation
  takes one extra flat-shaded pass. The private members used are those of the
  pinned dm-control 1.0.50.
  """

  def __init__(self, physics, height, width, camera_id, geom_labels):
    claim_gl()
    super().__init__(physics, height=height, width=width, camera_id=camera_id)
    self._geom_labels = geom_labels

  def render_kinds(self, kinds):
    """Returns {kind: image} for the requested kinds, top row first."""
    self.update()
    images = {}
    gl = self._physics.contexts.gl
    with gl.make_current() as ctx:
      if "rgb" in kinds or "depth" in kinds:
        ctx.call(self._render_and_read, "rgb" in kinds, "depth" in kinds)
        if "rgb" in kinds:
          images["rgb"] = gl.to_pixels(self._rgb_buffer).copy()
        if "depth" in kinds:
          images["depth"] = gl.to_pixels(self._depth_to_metres(self._depth_buffer))
      if "segmentation" in kinds:
        flags = {mujoco.mjtRndFlag.mjRND_SEGMENT: True, mujoco.mjtRndFlag.mjRND_IDCOLOR: True}
        with self.scene.override_flags(flags):
          ctx.call(self._render_and_read, True, False)
        images["segmentation"] = gl.to_pixels(self._segment_labels(self._rgb_buffer)).copy()
    return images

  def _render_and_read(self, rgb, depth):
    context = self._physics.contexts.mujoco.ptr
    mujoco.mjr_render(self._rect, self._scene.ptr, context)
    mujoco.mjr_readPixels(self._rgb_buffer if rgb else None, self._depth_buffer if depth else None,
                          self._rect, context)

  def _depth_to_metres(self, buffer):
    model = self._physics.model
    near = model.vis.map.znear * model.stat.extent
    far = model.vis.map.zfar * model.stat.extent
    return (near / (1 - buffer * (1 - near / far))).astype(np.float32)

  def _segment_labels(self, buffer):
    segid = (buffer[..., 0].astype(np.int32) + (buffer[..., 1].astype(np.int32) << 8)
             + (buffer[..., 2].astype(np.int32) << 16))
    scene = self._scene
    segid_label = np.full(scene.ngeom + 1, BACKGROUND_ID, dtype=np.int32)
    for geom in scene.geoms[:scene.ngeom]:
      if geom.segid >= 0 and geom.objtype == mujoco.mjtObj.mjOBJ_GEOM:
        segid_label[geom.segid + 1] = self._geom_labels[geom.objid + 1]
    return segid_label[np.clip(segid, 0, scene.ngeom)]


def camera_projection(physics, camera_id, height, width):
  """World-to-camera rotation, camera position and focal length in pixels."""
  rotation = physics.data.cam_xmat[camera_id].reshape(3, 3).T
  position = physics.data.cam_xpos[camera_id].copy()
  focal = 0.5 * height / np.tan(np.deg2rad(physics.model.cam_fovy[camera_id]) / 2)
  return rotation, position, focal


def project_points(points, rotation, position, focal, height, width):
  """Pixel (column, row) of world points and whether each lies in front of the camera."""
  local = (points - position) @ rotation.T   # camera frame: x right, y up, looking along -z
  depth = -local[..., 2]
  in_front = depth > 1e-6
  safe = np.where(in_front, depth, 1.0)
  column = (width - 1) / 2 + focal * local[..., 0] / safe
  row = (height - 1) / 2 - focal * local[..., 1] / safe
  return np.stack([column, row], axis=-1), in_front


_BOX_SIGNS = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)


def part_boxes(physics, camera_id, height, width, geom_ids, geom_part, num_parts):
  """Each part's 2D box [x_min, y_min, x_max, y_max] in pixels; -1s for parts out of view.

  Boxes bound the projected corners of the part's geoms' bounding boxes (amodal:
  occluded parts keep their box), clipped to the image.
  """
  model, data = physics.model, physics.data
  aabb = model.geom_aabb[geom_ids]
  corners_local = aabb[:, None, :3] + _BOX_SIGNS[None] * aabb[:, None, 3:]
  rot = data.geom_xmat[geom_ids].reshape(-1, 3, 3)
  corners = np.einsum("gij,gkj->gki", rot, corners_local) + data.geom_xpos[geom_ids][:, None]
  pixels, in_front = project_points(corners, *camera_projection(physics, camera_id, height, width),
                                    height, width)
  low = np.where(in_front[..., None], pixels, np.inf).min(axis=1)
  high = np.where(in_front[..., None], pixels, -np.inf).max(axis=1)
  box_low = np.full((num_parts, 2), np.inf)
  box_high = np.full((num_parts, 2), -np.inf)
  np.minimum.at(box_low, geom_part, low)
  np.maximum.at(box_high, geom_part, high)
  limit = np.array([width - 1, height - 1], dtype=float)
  visible = np.all(box_high >= 0, axis=1) & np.all(box_low <= limit, axis=1)
  boxes = np.concatenate([np.clip(box_low, 0, limit), np.clip(box_high, 0, limit)], axis=1)
  boxes[~visible] = -1.0
  return boxes
