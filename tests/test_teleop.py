"""Keyboard teleoperation, headless: key mapping, episode keys and recording."""

import h5py
import numpy as np
import pytest

import ikea_suite
from ikea_suite.datasets import hdf5
from ikea_suite.datasets import replay
from ikea_suite.teleop import keymap
from ikea_suite.teleop import session as session_lib

CURSOR_NAMES = ikea_suite.load("table_four_leg_lack", "cursor").task.action_names


def test_motion_keys_drive_their_axis_for_hold_steps():
  command = keymap.KeyboardCommand(CURSOR_NAMES, hold_steps=2)
  command.press(ord("W"))
  command.press(ord("F"))
  first, second, third = command.action(), command.action(), command.action()
  assert first[0] == 1.0 and first[2] == -1.0 and np.count_nonzero(first[:6]) == 2
  np.testing.assert_array_equal(second, first)
  assert not third[:6].any()
  assert first[6] == -1.0 and first[-1] == -1.0   # select off, no connect


def test_tab_switches_cursor_grip_toggles_connect_pulses():
  command = keymap.KeyboardCommand(CURSOR_NAMES)
  command.press(keymap.KEY_TAB)
  command.press(ord("U"))
  command.press(keymap.GRIP_KEY)
  command.press(keymap.CONNECT_KEY)
  action = command.action()
  assert action[7 + 5] == 1.0 and not action[:6].any()   # cursor 1 turns about +z
  assert action[7 + 6] == 1.0 and action[6] == -1.0 and action[-1] == 1.0
  assert command.action()[-1] == -1.0
  command.press(keymap.GRIP_KEY)
  assert command.action()[13] == -1.0
  assert command.press(keymap.KEY_ENTER) == "save"
  assert command.press(keymap.KEY_BACKSPACE) == "discard"


def test_arm_layouts_need_task_space():
  sawyer = ikea_suite.load("table_four_leg_lack", "sawyer").task.action_names
  assert keymap.KeyboardCommand(sawyer).num_agents == 1
  baxter = ikea_suite.load("table_four_leg_lack", "baxter").task.action_names
  assert keymap.KeyboardCommand(baxter).num_agents == 2
  joints = ikea_suite.load("table_four_leg_lack", "panda",
                           control_mode="joint_position").task.action_names
  with pytest.raises(ikea_suite.OptionValueError, match="task_space"):
    keymap.KeyboardCommand(joints)


def test_session_records_kept_episodes_that_replay_exactly(tmp_path):
  args = hdf5.env_args("table_four_leg_lack", "cursor", {"time_limit": 2.0})
  session = session_lib.TeleopSession(hdf5.load_env(args), args, seed=4)
  for key in (ord("W"), ord("W"), ord("R")):
    session.on_key(key)
  events = [session.step() for _ in range(5)]
  session.on_key(keymap.KEY_BACKSPACE)   # drop that attempt
  assert session.step() == "discard" and not session.episodes
  session.on_key(ord("D"))
  events = [session.step() for _ in range(6)]
  session.on_key(keymap.KEY_ENTER)
  assert session.step() == "save"
  events = [session.step() for _ in range(40)]   # runs into the 2 s time limit: kept
  assert events.count("done") == 1
  path = str(tmp_path / "teleop.hdf5")
  assert session.write(path) == 2
  with h5py.File(path, "r") as f:
    assert [f[f"data/{n}"].attrs["seed"] for n in hdf5.demo_names(f)] == [5, 6]
    actions = f["data/demo_0/actions"][()]
    assert actions.shape == (6, 15) and actions[0, 1] == -1.0 and actions[3, 1] == 0.0
    assert f["data/demo_1"].attrs["num_samples"] == 40
    assert f["data/demo_0/subtask/phase"][0] == b"teleop"
  assert all(r.max_divergence == 0.0 for r in replay.replay_file(path))


def test_teleop_options_open_arms_in_either_task_space_delta_mode():
  from ikea_suite.teleop import cli
  assert cli.load_options("cursor") == {}
  assert cli.load_options("sawyer") == {"control_mode": "task_space"}
  options = cli.load_options("panda", "impedance", 0.5)
  assert options == {"control_mode": "impedance", "scale": 0.5}
  env = hdf5.load_env(hdf5.env_args("table_four_leg_lack", "panda", options))
  assert keymap.KeyboardCommand(env.task.action_names).num_agents == 1
  with pytest.raises(ikea_suite.IkeaSuiteError, match="control_mode"):   # the Cursor has none
    hdf5.load_env(hdf5.env_args("table_four_leg_lack", "cursor", cli.load_options("cursor", "impedance")))


def test_teleop_without_a_display_says_so_and_points_to_the_headless_api(
    monkeypatch, capsys, tmp_path):
  from ikea_suite.teleop import cli
  monkeypatch.setattr(cli.sys, "platform", "linux")
  monkeypatch.delenv("DISPLAY", raising=False)
  monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
  with pytest.raises(ikea_suite.IkeaSuiteError, match="needs a display") as info:
    cli.check_display()
  assert "ikea_suite.teleop.session.TeleopSession" in str(info.value)
  out = tmp_path / "teleop.hdf5"
  assert cli.main(["--out", str(out)]) == 2
  err = capsys.readouterr().err
  assert "needs a display (neither DISPLAY nor WAYLAND_DISPLAY is set)" in err
  assert "TeleopSession" in err and not out.exists()


def test_teleop_with_a_display_glfw_cannot_open_says_so(monkeypatch):
  # MuJoCo's viewer would end the process there, past any handler: it is checked first.
  import glfw
  from ikea_suite.teleop import cli
  monkeypatch.setattr(cli.sys, "platform", "linux")
  monkeypatch.setenv("DISPLAY", ":77")
  monkeypatch.setattr(glfw, "init", lambda: False)
  with pytest.raises(ikea_suite.IkeaSuiteError,
                     match="needs a display \\(GLFW cannot open the display ':77'\\)"):
    cli.check_display()
