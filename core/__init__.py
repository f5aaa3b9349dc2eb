"""dolphinfit's headless engine: model, camera, renderer, fit, measurements and I/O.

Nothing under ``core`` imports Qt, pyvista or vtk; the GUI, the CLI and the tests share it.
"""
