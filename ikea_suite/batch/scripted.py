"""A scripted start and policy: a cursor carries the last missing part into place and connects.

`last_part_start` builds worlds where every part but the last of the
buildable order stands assembled and welded (at a random yaw), and the last
part floats near its assembled pose (a few cm and degrees off), with cursor 0
inside it and cursor 1 inside the root part. `carry_policy` reads the
privileged state: cursor 1 holds the assembly where it stands (as the CPU
oracle holds the root), cursor 0 holds the last part and steers it, with proportional steps on the part's own pose error (so the
grip's sag is corrected too), towards its pose relative to the assembled
group, with connect on every step. The start and the policy serve the
correctness test and the catalog script.
"""

import functools

import jax
import jax.numpy as jnp
import numpy as np

from ikea_suite.batch import observe
from ikea_suite.batch import rigid
from ikea_suite.batch import task_state
from ikea_suite.tasks import alignment
from ikea_suite.tasks import placement as cpu_placement

GAIN = 0.5          # fraction of the remaining pose error corrected per control step


def _design(env):
  spec = env.batch_model.spec
  return (np.array([p.pos for p in spec.parts]), np.array([p.rot for p in spec.parts]))


def _preassembled(env, last):
  """(group, connector_used, adjacency, active weld equality ids) with every design pair not
  touching part `last` joined, one weld per part pair, as connect_in_place does on the CPU."""
  bm = env.batch_model
  table, welds = bm.table, bm.welds
  pos, rot = _design(env)
  cpos, crot = table.world_frames(pos, rot)
  twist = alignment.align_pairs(cpos, crot, table).twist
  p = bm.num_parts
  group = np.where(np.arange(p) == last, last, [i for i in range(p) if i != last][0])
  used = np.zeros(len(table), dtype=bool)
  adjacency = np.zeros((p, p), dtype=bool)
  active = []
  for k in cpu_placement.design_pairs(bm.spec, table):
    a, b = table.pair_a[k], table.pair_b[k]
    pa, pb = int(table.part[a]), int(table.part[b])
    if last in (pa, pb) or used[a] or used[b]:
      continue
    used[[a, b]] = True
    if not adjacency[pa, pb]:
      valid = welds.twist_valid[k]
      slot = int(np.argmax(np.where(valid, np.cos(welds.twist_angles[k] - twist[k]), -np.inf)))
      active.append(int(bm.weld_eq[welds.weld_of[k, slot]]))
    adjacency[pa, pb] = adjacency[pb, pa] = True
  return group, used, adjacency, np.array(active, dtype=int)


def last_part_start(env, rng, offset=(0.02, 0.05), tilt=np.radians(6)):
  """One world (call inside env.precision(); vmap over keys for many).

  Args:
    env: a BatchAssembly.
    rng: PRNG key.
    offset: (min, max) distance (m) of the last part from its assembled position.
    tilt: largest rotation (radians) of the last part away from its assembled orientation.

  Returns:
    A State.
  """
  tables = env.tables
  last = int(np.asarray(tables.order)[-1])
  group, used, adjacency, active = _preassembled(env, last)
  pos, rot = (rigid.real(x) for x in _design(env))
  k_reset, k_yaw, k_dir, k_len, k_axis, k_angle = jax.random.split(rng, 6)
  state = env.reset(k_reset)
  yaw = rigid.rot_z(jax.random.uniform(k_yaw, (), minval=-np.pi, maxval=np.pi))
  pos = rigid.apply(yaw, pos) + jnp.array([0.0, 0.0, 1e-3])
  rot = yaw @ rot
  direction = jax.random.normal(k_dir, (3,))
  direction = direction.at[2].set(jnp.abs(direction[2]))     # never down into the floor
  direction = direction / jnp.linalg.norm(direction)
  shift = direction * jax.random.uniform(k_len, (), minval=offset[0], maxval=offset[1])
  axis = jax.random.normal(k_axis, (3,))
  turn = rigid.quat_to_mat(rigid.axis_angle_to_quat(
      axis / jnp.linalg.norm(axis) * jax.random.uniform(k_angle, (), minval=-tilt, maxval=tilt)))
  pos = pos.at[last].add(shift)
  rot = rot.at[last].set(turn @ rot[last])
  state = env.with_part_poses(state, pos, rot)
  eq_active = state.data.eq_active.at[jnp.asarray(active, dtype=jnp.int32)].set(True)
  # Cursor 0 inside the last part, cursor 1 inside the root part (it holds the incomplete
  # assembly up: a stool missing a side falls over, and shelving missing a ladder sags at its
  # free end until the ladder's snap would go 8 cm into the floor, which connect refuses),
  # each at its first collision box's centre.
  def centre(part):
    g = int(np.flatnonzero(np.asarray(env.batch_model.geom_part) == part)[0])
    return pos[part] + rigid.apply(rot[part], tables.geom_pos[g]
                                   + rigid.apply(tables.geom_rot[g], tables.geom_center[g]))
  root = int(np.asarray(tables.order)[0])
  task = state.task._replace(
      group=jnp.asarray(group, dtype=jnp.int32), connector_used=jnp.asarray(used),
      adjacency=jnp.asarray(adjacency), cursor_pos=jnp.stack([centre(last), centre(root)]))
  data = state.data.replace(eq_active=eq_active)
  return state._replace(data=data, task=task, obs=observe.observe(tables, task, data.qpos))


def _axis_angle(rot):
  """Rotation vector of (3, 3) rotations, angle < pi."""
  cos = jnp.clip((jnp.trace(rot) - 1) / 2, -1.0, 1.0)
  angle = jnp.arccos(cos)
  axis = jnp.array([rot[2, 1] - rot[1, 2], rot[0, 2] - rot[2, 0], rot[1, 0] - rot[0, 1]])
  return axis * (angle / jnp.maximum(2 * jnp.sin(angle), 1e-9))


def carry_policy(env, state):
  """The 15-entry action of one world: cursor 0 selects and steers the last part to its
  assembled pose relative to the root part, cursor 1 holds the root; connect always on."""
  tables, s = env.tables, env.settings
  last, root = tables.order[-1], tables.order[0]
  design_pos, design_rot = (rigid.real(x) for x in _design(env))
  pos, rot = task_state.part_poses(tables, state.data.qpos)
  relative_rot = design_rot[root].T @ design_rot[last]
  relative_pos = design_rot[root].T @ (design_pos[last] - design_pos[root])
  target_rot = rot[root] @ relative_rot
  target_pos = pos[root] + rot[root] @ relative_pos
  dt = s.control_timestep
  move = GAIN * (target_pos - pos[last]) / (s.cursor.move_speed * dt)
  turn = GAIN * _axis_angle(target_rot @ rot[last].T) / (s.cursor.rotate_speed * dt)
  # Turning the cursor swings the part about the cursor: move the cursor to cancel the swing.
  lever = pos[last] - state.task.cursor_pos[0]
  swing = jnp.cross(GAIN * _axis_angle(target_rot @ rot[last].T), lever)
  move = move - swing / (s.cursor.move_speed * dt)
  cursor0 = jnp.concatenate([move, turn, jnp.ones(1)])
  cursor1 = jnp.concatenate([jnp.zeros(6), jnp.ones(1)])   # holds the assembly where it is
  return jnp.clip(jnp.concatenate([cursor0, cursor1, jnp.ones(1)]), -1.0, 1.0)


@functools.lru_cache(maxsize=8)
def _compiled(env):
  """The vmapped, jitted start and policy of `env`, kept so repeated runs compile once."""
  return (jax.jit(jax.vmap(lambda k: last_part_start(env, k))),
          jax.jit(jax.vmap(lambda st: carry_policy(env, st))))


def completion_steps(env, num_worlds, steps, seed=0):
  """Runs the carry policy from `last_part_start` in `num_worlds` worlds for up to `steps`
  steps (fewer once every world has completed).

  Returns:
    (num_worlds,) int array: the step (1-based) at which each world completed, 0 if it did not.
  """
  start, policy = _compiled(env)
  with env.precision():
    state = start(jax.random.split(jax.random.PRNGKey(seed), num_worlds))
    completed = np.zeros(num_worlds, dtype=int)
    for step in range(1, steps + 1):
      state = env.step_batch(state, policy(state))
      # Auto-reset starts a fresh episode in a completed world: keep its first completion.
      success = np.asarray(state.metrics["success"])
      completed = np.where((completed == 0) & success, step, completed)
      if completed.all():
        break
  return completed


def run(env, num_worlds, steps, seed=0):
  """Fraction of `num_worlds` worlds whose assembly the carry policy completed within `steps`
  steps (see completion_steps)."""
  return float((completion_steps(env, num_worlds, steps, seed) > 0).mean())
