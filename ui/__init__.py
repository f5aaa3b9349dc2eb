"""PySide6 widgets and the pyvistaqt 3D viewer; numerical work runs in workers, never here."""
