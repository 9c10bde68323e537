"""examples/ideal_gas.ipynb runs from top to bottom without an error.

The notebook asserts its own physics (energy conservation, the Rayleigh speed
distribution, Z against the hard-disk equation of state), so running it here is
a test of the physics as well as of the example. It is executed in memory, in a
temporary working directory, and never saved: the repository keeps it without
outputs, which the second test checks.
"""

import pathlib

# Not skipped when missing: the test command installs them (install-deps.sh --test).
import ipykernel  # noqa: F401  (the kernel the notebook runs in)
import matplotlib  # noqa: F401
import nbclient
import nbformat

NOTEBOOK = pathlib.Path(__file__).resolve().parents[2] / "examples" / "ideal_gas.ipynb"
CELL_TIMEOUT_S = 300  # the slowest cell takes a few seconds on a 2-core machine


def test_ideal_gas_notebook_runs(tmp_path):
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    client = nbclient.NotebookClient(
        notebook,
        timeout=CELL_TIMEOUT_S,
        kernel_name="python3",
        resources={"metadata": {"path": str(tmp_path)}},
    )
    # Raises nbclient.exceptions.CellExecutionError (with the cell's traceback,
    # e.g. a failed assert) or CellTimeoutError.
    client.execute()
    errors = [
        output
        for cell in notebook.cells
        if cell.cell_type == "code"
        for output in cell.get("outputs", [])
        if output.get("output_type") == "error"
    ]
    assert not errors, errors


def test_ideal_gas_notebook_is_committed_without_outputs():
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    nbformat.validate(notebook)
    for index, cell in enumerate(notebook.cells):
        if cell.cell_type == "code":
            assert cell.outputs == [], f"cell {index} has outputs: clear them before committing"
            assert cell.execution_count is None, f"cell {index} has an execution count"
