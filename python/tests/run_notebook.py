"""Run by ctest notebook_quick_start, not by pytest: executes a notebook in a Jupyter kernel
(Debian's python3-nbclient, python3-nbformat, python3-ipykernel; the kernel inherits
PYTHONPATH), as `jupyter nbconvert --execute` does, and fails on the first cell that raises,
naming it. argv[1]: the notebook."""
import sys

import nbclient
import nbformat

notebook = nbformat.read(sys.argv[1], as_version=4)
nbformat.validate(notebook)
client = nbclient.NotebookClient(notebook, kernel_name="python3", timeout=600, allow_errors=False)
try:
    client.execute()
except nbclient.exceptions.CellExecutionError as error:
    print(f"{sys.argv[1]}: a cell raised:\n{error}", file=sys.stderr)
    sys.exit(1)
code = [cell for cell in notebook.cells if cell.cell_type == "code"]
printed = sum(1 for cell in code for output in cell.outputs if output.get("output_type") == "stream")
assert all(cell.execution_count for cell in code), "a code cell did not run"
print(f"{sys.argv[1]}: {len(code)} code cells executed, {printed} printed output")
