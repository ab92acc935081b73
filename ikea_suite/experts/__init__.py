"""Scripted experts: policies that assemble furniture through the action vector a learner sends.

    env = ikea_suite.load("table_four_leg_lack", "sawyer", seed=1000)   # at its work scale
    expert = ikea_suite.experts.make_expert(env)
    expert.reset(); timestep = env.reset()
    while not timestep.last():
      timestep = env.step(expert(timestep))

They read privileged state (part and connector poses, the assembly graph) but move
parts only with the robot: the Cursor oracle (cursor_oracle.py), the single-arm expert
for the Sawyer, Panda and Jaco (single_arm.py) and the Baxter's two-arm expert
(bimanual.py). Which expert drives which robot, in which control modes, and which
furniture it assembles at what scale is the registry's (registry.py, with the
measurements in supported.json); `supported(robot)` lists the furniture an expert
completed in at least 80% of its episodes on fresh seeds, and make_expert refuses any
other furniture, or another scale than the measured one, unless require_supported=False.

The arm experts' skills, each in its own module: the top-down grasp (top_down_grasp.py,
with finger_room.py and below_work_scale.py), which part next (next_part.py), the mate
and twist to bring it to (mating.py), routes clear of the assembly (clearance.py),
turning the assembly over (turn_over.py), task-space servoing (arm_motion.py), reading
privileged state (sensing.py, part_geometry.py); which parts fit a gripper
(gripper_fit.py) and the scale each model is assembled at (work_scale.py).
"""

from ikea_suite.experts.registry import Measurement
from ikea_suite.experts.registry import ROBOTS
from ikea_suite.experts.registry import check_supported
from ikea_suite.experts.registry import make_expert
from ikea_suite.experts.registry import measurement
from ikea_suite.experts.registry import measurements
from ikea_suite.experts.registry import supported
from ikea_suite.experts.registry import supported_pairs
from ikea_suite.experts.registry import supported_scale

__all__ = ["Measurement", "ROBOTS", "check_supported", "make_expert", "measurement", "measurements", "supported",
           "supported_pairs", "supported_scale"]
