"""The README's two set-up commands are the ones CI runs."""

import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[1]


def ci_commands():
  lines = (ROOT / ".ci" / "run").read_text().splitlines()
  return [line for line in lines if line.startswith((
      "python3 -m venv", ".venv/bin/python -m pytest"))]


def test_ci_runs_the_readme_commands_verbatim():
  commands = ci_commands()
  assert len(commands) == 2
  readme = (ROOT / "README.md").read_text()
  for command in commands:
    assert f"\n{command}\n" in readme, command


def test_readme_starts_with_the_set_up():
  readme = (ROOT / "README.md").read_text()
  assert readme.index("python3 -m venv") < readme.index("## ")


def test_readme_is_a_front_door_of_at_most_400_lines():
  readme = (ROOT / "README.md").read_text()
  assert len(readme.splitlines()) <= 400
  for page in ("docs/index.md", "docs/options.md", "docs/experts.md", "docs/benchmarks.md",
               "CHANGELOG.md"):
    assert page in readme or page.removeprefix("docs/") in readme, page
