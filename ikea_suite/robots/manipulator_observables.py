"""Observables of a fixed-base arm robot (robots/manipulator.py)."""

from dm_control import composer
from dm_control.composer.observation import observable

from ikea_suite import mujoco_arrays


class ManipulatorObservables(composer.Observables):
  """Arm joint positions and velocities, tool poses, gripper openings; wrist cameras on request."""

  def __init__(self, entity):
    super().__init__(entity)
    if entity.wrist_camera_size is not None:
      height, width = entity.wrist_camera_size
      for arm in entity.arms:
        self.add_observable(f"{arm.prefix}wrist_camera",
                            observable.MJCFCamera(arm.camera, height=height, width=width))

  @composer.observable
  def joint_positions(self):
    return mujoco_arrays.FreshGeneric(self._entity.joint_positions)

  @composer.observable
  def joint_velocities(self):
    return mujoco_arrays.FreshGeneric(self._entity.joint_velocities)

  @composer.observable
  def tcp_positions(self):
    return mujoco_arrays.FreshGeneric(self._entity.tcp_positions)

  @composer.observable
  def tcp_quaternions(self):
    return mujoco_arrays.FreshGeneric(self._entity.tcp_quaternions)

  @composer.observable
  def gripper_opening(self):
    return mujoco_arrays.FreshGeneric(self._entity.gripper_openings)
