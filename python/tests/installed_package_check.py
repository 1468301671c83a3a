"""Run by ctest python_package_installed (python/installed_package_test.cmake), not by pytest:
the package installed into a fresh prefix works from there alone. argv[1]: the installed site
folder."""
import inspect
import os
import sys
import tempfile

site_dir = os.path.realpath(sys.argv[1])
assert "PYTHONPATH" not in os.environ
assert not any(os.path.isdir(os.path.join(p, "lgvi")) for p in sys.path if p), "an lgvi is already on the path"
import site  # noqa: E402

site.addsitedir(site_dir)
import lgvi  # noqa: E402

package = os.path.join(site_dir, "lgvi")
assert os.path.realpath(lgvi.__file__).startswith(package + os.sep), lgvi.__file__
assert lgvi.__version__.count(".") == 2, lgvi.__version__
for stub in ("__init__.pyi", "py.typed"):
    assert os.path.isfile(os.path.join(package, stub)), stub
assert list(inspect.signature(lgvi.so3.exp).parameters) == ["w"]
if lgvi.has_harness:
    # The shipped data comes from the package's own data folder, not the source tree.
    for kind, folder in lgvi.data_dirs().items():
        assert os.path.realpath(folder).startswith(os.path.join(package, "data") + os.sep), (kind, folder)
        assert os.path.isdir(folder), folder
    names = lgvi.scene_names()
    assert "pendulum" in names and "ocp-pendulum" in names, names
    run = lgvi.simulate(lgvi.load_scene("pendulum", t_final=0.05))
    assert run["R"].shape[1:] == (3, 3) and run["summary"]["status"] == "completed", run["summary"]["status"]
    ocp = lgvi.solve_ocp("pendulum", steps=20)
    assert ocp["converged"] and ocp["summary"]["W"].shape == (3, 3)
    with tempfile.TemporaryDirectory() as out:
        # A study file of the user's naming a shipped scene.
        study = os.path.join(out, "tiny.toml")
        with open(study, "w") as f:
            f.write('name = "tiny"\nmetrics = ["energy"]\nscenes = [{ scene = "free-body", horizons = [1.0] }]\n'
                    'methods = ["lgvi"]\nsteps = [100]\ntolerances = [1e-6]\n')
        rows = lgvi.run_study(study, os.path.join(out, "study"))
        assert [r["status"] for r in rows] == ["completed"], rows
print("installed package: ok,", package)
