"""Entry points only: the ``dolphinfit`` command line and (later) the GUI launcher."""
