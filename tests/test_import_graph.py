"""No two files of the house import each other, directly or round a loop (the layers between
packages are import-linter's contracts in pyproject.toml; this holds within a package too)."""

import graphlib

import grimp


def test_no_module_imports_itself_round_a_loop():
    graph = grimp.build_graph("dolphinfit.core", "dolphinfit.ui", "dolphinfit.app", cache_dir=None)
    imports = {module: graph.find_modules_directly_imported_by(module)
               for module in graph.modules}
    assert len(imports) > 200
    try:
        graphlib.TopologicalSorter(imports).prepare()
    except graphlib.CycleError as cycle:
        raise AssertionError(f"an import loop: {' → '.join(cycle.args[1])}") from None
