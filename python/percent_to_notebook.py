"""Writes a Jupyter notebook (nbformat 4, no outputs) from a Python file in the "percent"
format: a line `# %%` starts a code cell, `# %% [markdown]` a markdown cell whose lines drop
their leading "# ".

    python3 python/percent_to_notebook.py examples/python/quick_start.py examples/python/quick_start.ipynb

python_tests (test_package.py) fails when the committed notebook is not what this writes.
"""
import json
import sys


def cells(text):
    out, kind, lines = [], None, []

    def close():
        while lines and not lines[-1].strip():
            lines.pop()
        if kind is not None and lines:
            source = [line + "\n" for line in lines[:-1]] + [lines[-1]]
            cell = {"cell_type": kind, "metadata": {}, "source": source}
            if kind == "code":
                cell.update(execution_count=None, outputs=[])
            out.append(cell)

    for line in text.splitlines():
        if line.startswith("# %%"):
            close()
            kind, lines = ("markdown" if "[markdown]" in line else "code"), []
            continue
        if kind == "markdown":
            line = line[2:] if line.startswith("# ") else line.lstrip("#")
        if kind is not None and (lines or line.strip()):
            lines.append(line)
    close()
    return out


def notebook(text):
    document = {
        "cells": cells(text),
        "metadata": {"kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"},
                     "language_info": {"name": "python"}},
        "nbformat": 4,
        "nbformat_minor": 5,
    }
    for i, cell in enumerate(document["cells"]):
        cell["id"] = f"cell-{i}"
    return json.dumps(document, indent=1, ensure_ascii=False) + "\n"


if __name__ == "__main__":
    with open(sys.argv[1]) as source:
        text = notebook(source.read())
    with open(sys.argv[2], "w") as target:
        target.write(text)
