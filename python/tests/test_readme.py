"""The README's Python example runs as written."""
import re

from conftest import REPOSITORY


def test_the_readme_example_runs(tmp_path, capsys, monkeypatch):
    readme = (REPOSITORY / "README.md").read_text()
    section = readme[readme.index("\n## Python\n"):]
    example = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    monkeypatch.chdir(tmp_path)
    exec(compile(example, "README.md (Python)", "exec"), {})
    assert (tmp_path / "gas.gsd").stat().st_size > 0
    assert len(capsys.readouterr().out.split()) == 3
