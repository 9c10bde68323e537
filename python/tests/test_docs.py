"""The documentation works as written: every fenced code block of README.md
and docs/**/*.md runs, the site builds without a warning, and the benchmark
tables are what bench/results/tables.py makes of the committed JSON.

Each page's blocks run in order, in a temporary folder of the page's own
(build/, scenes/, bench/, examples/ and tests/ link to the repository's), so
a command's outputs land there and a later block of the page can read them.

  sh, bash, shell  run by bash -e; the block must exit 0
  console          `$ command` lines, each followed by the output it must
                   print (stdout and stderr together; `...` stands for any
                   text); the exit status is not checked
  python           run by this Python, where `pip install .` put carom
  toml             a scene file: `build/carom run --scene FILE`
  cpp, cmake       a verbatim part of a file under examples/ that the ctest
                   suite builds and runs (tests/build_example.cmake)
  text             output shown, not run

A block that cannot run here carries, on the line right before it,
`<!-- not run: REASON -->` with a REASON from NOT_RUN_REASONS.
"""
import collections
import os
import pathlib
import re
import subprocess
import sys
import textwrap

import pytest

from conftest import REPOSITORY

NOT_RUN_REASONS = {
    "installs system packages": "it changes the machine (apt-get, pip into a fresh environment)",
    "needs a GPU": "it names an NVIDIA device",
    "opens a window": "it needs a display and a person",
    "runs for minutes": "it takes longer than the docs tests allow",
    "serves until stopped": "a web server runs until it is stopped (tests/web serves the page itself)",
    "runs under mpirun": "the tests run the same under mpirun (tests/mpi_tests.cmake, the examples' tests, "
                         "python/tests/test_mpi.py)",
}
RUN = {"sh": "shell", "bash": "shell", "shell": "shell", "console": "console", "python": "python",
       "toml": "scene", "cpp": "example", "c++": "example", "cmake": "example", "text": "output"}
LINKED = ["build", "scenes", "bench", "examples", "tests"]
BLOCK_TIMEOUT = 120
README_MAX_LINES = 200

Block = collections.namedtuple("Block", "page line language text not_run")


def pages():
    return [REPOSITORY / "README.md"] + sorted((REPOSITORY / "docs").rglob("*.md"))


def blocks_of(page: pathlib.Path):
    """The fenced code blocks of a Markdown page, with the not-run reason
    given on the line before each (None when it runs)."""
    lines = page.read_text().splitlines()
    found = []
    i = 0
    while i < len(lines):
        opening = re.match(r"^ {0,3}(`{3,}|~{3,})\s*([^`\s]*)", lines[i])
        if not opening:
            i += 1
            continue
        fence, language = opening.group(1), opening.group(2)
        previous = next((lines[j].strip() for j in range(i - 1, -1, -1) if lines[j].strip()), "")
        marker = re.fullmatch(r"<!--\s*not run:\s*(.*?)\s*-->", previous)
        end = i + 1
        while end < len(lines) and not re.match(r"^ {0,3}" + fence[0] + "{" + str(len(fence)) + r",}\s*$", lines[end]):
            end += 1
        found.append(Block(page.relative_to(REPOSITORY).as_posix(), i + 1, language,
                           "\n".join(lines[i + 1:end]) + "\n", marker.group(1) if marker else None))
        i = end + 1
    return found


def all_blocks():
    return [block for page in pages() for block in blocks_of(page)]


def workspace(tmp_path: pathlib.Path) -> pathlib.Path:
    for name in LINKED:
        (tmp_path / name).symlink_to(REPOSITORY / name)
    return tmp_path


def environment():
    env = dict(os.environ)
    env["PATH"] = str(pathlib.Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    return env


def run(command, cwd, block, **options):
    try:
        return subprocess.run(command, cwd=cwd, env=environment(), timeout=BLOCK_TIMEOUT, text=True,
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, **options)
    except subprocess.TimeoutExpired:
        pytest.fail(f"{block.page}:{block.line}: did not finish within {BLOCK_TIMEOUT} s")


def expect_success(result, block):
    if result.returncode != 0:
        pytest.fail(f"{block.page}:{block.line}: the {block.language} block exited with status "
                    f"{result.returncode}\n--- block\n{block.text}--- output\n{result.stdout[-4000:]}")


def console_steps(block):
    """(command, expected output) pairs of a console block."""
    steps = []
    for line in block.text.splitlines():
        if line.startswith("$ "):
            steps.append([line[2:], []])
        elif steps:
            steps[-1][1].append(line)
        elif line.strip():
            pytest.fail(f"{block.page}:{block.line}: a console block starts with a `$ ` command")
    return [(command, "\n".join(output)) for command, output in steps]


def matches(expected: str, actual: str) -> bool:
    tidy = lambda text: "\n".join(line.rstrip() for line in text.strip().splitlines())
    pattern = ".*?".join(re.escape(part) for part in tidy(expected).split("..."))
    return re.fullmatch(pattern, tidy(actual), re.S) is not None


def example_files():
    """The files of examples/ that the ctest suite builds and runs, with their lines."""
    cmake = (REPOSITORY / "examples" / "CMakeLists.txt").read_text()
    runner = (REPOSITORY / "tests" / "build_example.cmake").read_text()
    files = {"examples/CMakeLists.txt": cmake}
    for target, source in re.findall(r"add_executable\((\w+) (\w+\.cpp)\)", cmake):
        assert re.search(r"/build/" + target + r"\b", runner), f"tests/build_example.cmake does not run {target}"
        files["examples/" + source] = (REPOSITORY / "examples" / source).read_text()
    return files


def is_part_of(block_text: str, text: str) -> bool:
    wanted = textwrap.dedent(block_text).rstrip("\n").splitlines()
    lines = [line.rstrip() for line in text.splitlines()]
    return any(textwrap.dedent("\n".join(lines[i:i + len(wanted)])).splitlines() == wanted
               for i in range(len(lines) - len(wanted) + 1))


def run_block(block, folder):
    kind = RUN[block.language]
    if kind == "shell":
        expect_success(run(["bash", "-e", "-c", block.text], folder, block), block)
    elif kind == "console":
        for command, expected in console_steps(block):
            result = run(["bash", "-c", command], folder, block)
            if not matches(expected, result.stdout):
                pytest.fail(f"{block.page}:{block.line}: `{command}` printed\n{result.stdout}\nnot\n{expected}")
    elif kind == "python":
        script = folder / f"block_{block.line}.py"
        script.write_text(block.text)
        expect_success(run([sys.executable, script.name], folder, block), block)
    elif kind == "scene":
        scene = folder / f"scene_{block.line}.toml"
        scene.write_text(block.text)
        expect_success(run(["build/carom", "run", "--scene", scene.name, "--quiet"], folder, block), block)
    elif kind == "example":
        files = example_files()
        if not any(is_part_of(block.text, text) for text in files.values()):
            pytest.fail(f"{block.page}:{block.line}: this {block.language} block is not a verbatim part of "
                        f"any of {sorted(files)}, which the ctest suite builds and runs")


def test_every_block_has_a_known_language_and_reason():
    problems = []
    for block in all_blocks():
        if block.language.startswith("{"):
            continue  # a MyST directive (toctree, include, the references), not code
        if block.language not in RUN:
            problems.append(f"{block.page}:{block.line}: language {block.language!r}; allowed: {sorted(RUN)}")
        if block.not_run is not None and block.not_run not in NOT_RUN_REASONS:
            problems.append(f"{block.page}:{block.line}: not run: {block.not_run!r}; allowed reasons: "
                            f"{sorted(NOT_RUN_REASONS)}")
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("page", [p.relative_to(REPOSITORY).as_posix() for p in pages()])
def test_the_blocks_of_the_page_run(page, tmp_path, carom_exe):
    folder = workspace(tmp_path)
    for block in blocks_of(REPOSITORY / page):
        if block.language in RUN and block.not_run is None:
            run_block(block, folder)


def test_summary(capsys):
    """How many blocks run, and which do not and why (printed with the results)."""
    counts = collections.Counter()
    not_run = []
    for block in all_blocks():
        if block.language.startswith("{") or block.language not in RUN:
            continue
        kind = RUN[block.language]
        if kind == "output":
            counts["output shown"] += 1
        elif block.not_run is not None:
            not_run.append(f"  {block.page}:{block.line} ({block.language}): {block.not_run}")
        else:
            counts[kind] += 1
    with capsys.disabled():
        ran = sum(n for kind, n in counts.items() if kind != "output shown")
        print(f"\ndocs: {ran} code blocks run ({', '.join(f'{n} {k}' for k, n in sorted(counts.items()) if k != 'output shown')}), "
              f"{len(not_run)} not run, {counts['output shown']} output blocks shown")
        for line in not_run:
            print(line)
    assert counts, "no code blocks found"


def test_the_readme_is_short():
    lines = (REPOSITORY / "README.md").read_text().splitlines()
    assert len(lines) <= README_MAX_LINES, f"README.md has {len(lines)} lines; at most {README_MAX_LINES}"


def test_the_site_builds_without_warnings(tmp_path):
    result = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
                             "-d", str(tmp_path / "doctrees"), "docs", str(tmp_path / "html")],
                            cwd=REPOSITORY, text=True, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=600)
    assert result.returncode == 0, result.stdout[-8000:]
    assert (tmp_path / "html" / "index.html").is_file()


def test_the_benchmark_tables_are_generated_from_the_json():
    result = subprocess.run([sys.executable, "bench/results/tables.py", "--stdout"], cwd=REPOSITORY, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=60)
    assert result.returncode == 0, result.stderr
    committed = (REPOSITORY / "bench" / "results" / "README.md").read_text()
    assert committed == result.stdout, ("bench/results/README.md is not what bench/results/tables.py writes "
                                        "from the JSON: run `python3 bench/results/tables.py`")
