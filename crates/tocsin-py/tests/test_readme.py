"""The README's Python quickstart runs as written."""

import pathlib
import re


def test_readme_python_quickstart_runs():
    readme = (pathlib.Path(__file__).resolve().parents[3] / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", readme, re.S)
    assert blocks, "the README has a Python quickstart"
    for code in blocks:
        exec(compile(code, "README.md", "exec"), {})
