"""Rendering throughput of the image observations next to the state-only step rate.

For each image configuration (RGB; RGB + depth + segmentation) and size, with
one camera: env steps/s with that observation (physics, task and rendering
together), and frames/s of the renderer alone on a fixed scene. The first row
is the state-only env (no camera) for reference. Usage:

    MUJOCO_GL=egl python benchmarks/render_throughput.py [--steps 200] [--sizes 84 256] [--write]

--write also puts the table, headed by the command, date, machine and versions, into
docs/benchmarks.md (scripts/make_docs.py's markers).
"""

import argparse
import os
import pathlib
import platform
import sys
import time

os.environ.setdefault("MUJOCO_GL", "egl")   # headless by default; must precede dm_control

import numpy as np  # pylint: disable=g-import-not-at-top

import ikea_suite  # pylint: disable=g-import-not-at-top

ROOT = pathlib.Path(__file__).resolve().parents[1]
CONFIGS = (("rgb", ("rgb",)), ("rgb+depth+seg", ("rgb", "depth", "segmentation")))


def env_steps_per_second(env, steps, rng):
  spec = env.action_spec()
  env.reset()
  actions = rng.uniform(-1, 1, size=(steps,) + spec.shape)
  actions[:, -1] = -1.0   # no connect: measure stepping and rendering
  start = time.perf_counter()
  for action in actions:
    if env.step(action).last():
      env.reset()
  return steps / (time.perf_counter() - start)


def render_frames_per_second(env, camera, kinds, frames):
  """The renderer alone: the same scene drawn `frames` times."""
  rig = next(e for e in env.task.arena.iter_entities() if e.mjcf_model.model == "cameras")
  renderer = rig.renderer(env.physics, camera)
  renderer.render_kinds(kinds)   # warm up: GL context and texture upload
  start = time.perf_counter()
  for _ in range(frames):
    renderer.render_kinds(kinds)
  return frames / (time.perf_counter() - start)


def gl_description(env):
  """The OpenGL renderer string of the env's context, e.g. 'llvmpipe (LLVM 15.0.7, 256 bits)'."""
  try:
    from OpenGL import GL  # pylint: disable=g-import-not-at-top
    with env.physics.contexts.gl.make_current() as ctx:
      return ctx.call(lambda: GL.glGetString(GL.GL_RENDERER).decode())
  except Exception as error:  # pylint: disable=broad-except
    return f"unknown ({error})"


def cpu_description():
  try:
    with open("/proc/cpuinfo") as f:
      names = [line.split(":", 1)[1].strip() for line in f if line.startswith("model name")]
    return names[0]
  except (OSError, IndexError):
    return platform.processor() or platform.machine()


def main():
  parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
  parser.add_argument("--furniture", default=ikea_suite.DEFAULT_FURNITURE)
  parser.add_argument("--camera", default="front")
  parser.add_argument("--steps", type=int, default=200)
  parser.add_argument("--sizes", type=int, nargs="+", default=[84, 256])
  parser.add_argument("--write", action="store_true",
                      help="also write the table into docs/benchmarks.md")
  args = parser.parse_args()
  rng = np.random.default_rng(0)

  state_env = ikea_suite.load(args.furniture, "cursor", seed=0)
  state_rate = env_steps_per_second(state_env, max(args.steps, 1000), rng)
  rows = [("state only", "-", state_rate, None)]
  renderer_name = None
  for size in args.sizes:
    for label, kinds in CONFIGS:
      env = ikea_suite.load(args.furniture, "cursor", seed=0, cameras=(args.camera,),
                            camera_outputs=kinds, image_size=size)
      step_rate = env_steps_per_second(env, args.steps, rng)
      frame_rate = render_frames_per_second(env, args.camera, kinds, args.steps)
      renderer_name = renderer_name or gl_description(env)
      rows.append((label, f"{size}x{size}", step_rate, frame_rate))
      env.close()

  intro = [f"MUJOCO_GL={os.environ['MUJOCO_GL']}, GL renderer: {renderer_name}",
           f"CPU: {cpu_description()}, {os.cpu_count()} cores; "
           f"furniture {args.furniture}, camera {args.camera!r}, {args.steps} steps per row"]
  table = [f"| {'observation':<14} | {'size':<7} | {'env steps/s':>11} | {'render frames/s':>15} |",
           f"|{'-' * 16}|{'-' * 9}|{'-' * 13}|{'-' * 17}|"]
  for label, size, step_rate, frame_rate in rows:
    frames = "-" if frame_rate is None else f"{frame_rate:.0f}"
    table.append(f"| {label:<14} | {size:<7} | {step_rate:>11.0f} | {frames:>15} |")
  print("\n".join(intro + [""] + table))
  if args.write:
    sys.path.insert(0, str(ROOT / "scripts"))
    import make_docs  # pylint: disable=g-import-not-at-top
    body = "\n\n".join(intro) + "\n\n" + "\n".join(table) + "\n"
    make_docs.write_block(ROOT / "docs" / "benchmarks.md", "render-throughput", body,
                          make_docs.invoked_command())


if __name__ == "__main__":
  main()
