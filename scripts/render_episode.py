"""Renders one episode of the scripted Cursor oracle to a video file.

    MUJOCO_GL=egl python scripts/render_episode.py --out episode.mp4
    MUJOCO_GL=egl python scripts/render_episode.py --cameras front top --goal --out episode.gif

Frames are the environment's own camera observations (one per control step,
cameras side by side, optionally followed by the goal image). MP4 needs
`imageio` and `imageio-ffmpeg` (pip install "ikea_suite[video]"), GIF needs
`imageio` with Pillow; without them the frames are written as numbered PNGs
into a folder next to `--out`.
"""

import argparse
import os
import pathlib
import sys

os.environ.setdefault("MUJOCO_GL", "egl")   # headless by default; must precede dm_control

import numpy as np  # pylint: disable=g-import-not-at-top

import ikea_suite  # pylint: disable=g-import-not-at-top
from ikea_suite.experts import cursor_oracle  # pylint: disable=g-import-not-at-top

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from randomized_contact_sheet import write_png  # pylint: disable=g-import-not-at-top


def episode_frames(env, cameras, goal, max_steps):
  """Yields one tiled RGB frame per control step while the oracle assembles the furniture."""
  oracle = cursor_oracle.CursorOracle(env)
  timestep = env.reset()
  oracle.reset()
  steps = 0
  while True:
    images = [timestep.observation[f"cameras/{name}_rgb"] for name in cameras]
    if goal:
      images.append(timestep.observation[f"cameras/{cameras[0]}_goal_rgb"])
    yield np.concatenate(images, axis=1), timestep
    if timestep.last() or steps >= max_steps:
      return
    timestep = env.step(oracle(timestep))
    steps += 1


def _video_writer(path, fps):
  """An imageio writer for `path`, or None when imageio (or its ffmpeg) is missing."""
  try:
    import imageio.v2 as imageio  # pylint: disable=g-import-not-at-top
    if path.suffix == ".mp4":
      import imageio_ffmpeg  # pylint: disable=g-import-not-at-top,unused-import
      return imageio.get_writer(path, fps=fps, macro_block_size=8)
    return imageio.get_writer(path, duration=1000 / fps, loop=0)
  except ImportError:
    return None


def write_video(frames, path, fps):
  """Writes frames to `path`; falls back to PNG frames in a folder. Returns what was written."""
  path = pathlib.Path(path)
  writer = _video_writer(path, fps)
  if writer is None:
    folder = path.with_suffix("")
    folder = folder.with_name(folder.name + "_frames")
    folder.mkdir(parents=True, exist_ok=True)
    count = 0
    for count, frame in enumerate(frames, start=1):
      write_png(folder / f"frame_{count - 1:05d}.png", frame)
    return folder, count
  count = 0
  with writer:
    for count, frame in enumerate(frames, start=1):
      writer.append_data(frame)
  return path, count


def main():
  parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
  parser.add_argument("--furniture", default=ikea_suite.DEFAULT_FURNITURE)
  parser.add_argument("--seed", type=int, default=0)
  parser.add_argument("--cameras", nargs="+", default=["front"], help="tiled left to right")
  parser.add_argument("--size", type=int, nargs="+", default=[240, 320],
                      help="height [width] of each camera image")
  parser.add_argument("--goal", action="store_true", help="append the goal image to each frame")
  parser.add_argument("--scene", default="default", help="scene preset")
  parser.add_argument("--randomize", nargs="*", default=None,
                      help="randomization factors or groups (physics, visual, all)")
  parser.add_argument("--preassembled", type=int, default=0)
  parser.add_argument("--max-steps", type=int, default=3000)
  parser.add_argument("--out", default="episode.mp4", help=".mp4 or .gif")
  args = parser.parse_args()
  size = tuple(args.size) if len(args.size) == 2 else args.size[0]
  env = ikea_suite.load(args.furniture, "cursor", seed=args.seed, scene=args.scene,
                        randomize=args.randomize or None, preassembled=args.preassembled,
                        cameras=tuple(args.cameras), image_size=size, goal_image=args.goal)
  last = {}

  def frames():
    for frame, timestep in episode_frames(env, args.cameras, args.goal, args.max_steps):
      last["timestep"] = timestep
      yield frame

  fps = round(1.0 / env.control_timestep())
  written, count = write_video(frames(), args.out, fps)
  state = env.task.state
  print(f"wrote {written}: {count} frames at {fps} fps; "
        f"{len(state.connections)} connections made, complete={state.complete}")


if __name__ == "__main__":
  main()
