"""Installed, the repository's folders are one namespace: every package folder is listed in
pyproject.toml as dolphinfit.FOLDER…, and no module imports the folders by their bare names
(which work only from a clone, never from the wheel)."""

import ast
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FOLDERS = ("core", "app", "ui", "vtk_clips")


def test_every_package_folder_is_listed_under_the_dolphinfit_namespace():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    found = {"dolphinfit." + ".".join(init.parent.relative_to(ROOT).parts)
             for folder in FOLDERS for init in (ROOT / folder).rglob("__init__.py")}
    assert len(found) >= 20
    assert set(config["packages"]) == found | {"dolphinfit.resources"}
    assert config["package-dir"] == {f"dolphinfit.{f}": f for f in (*FOLDERS, "resources")}


def test_no_module_imports_a_folder_by_its_bare_name():
    bare = []
    for folder in (*FOLDERS, "tests", "docs"):
        for path in (ROOT / folder).rglob("*.py"):
            for node in ast.walk(ast.parse(path.read_text(), str(path))):
                names = ([alias.name for alias in node.names] if isinstance(node, ast.Import)
                         else [node.module or ""] if isinstance(node, ast.ImportFrom)
                         and node.level == 0 else [])
                bare += [f"{path.relative_to(ROOT)}: {name}" for name in names
                         if name.split(".")[0] in FOLDERS]
    assert bare == []
