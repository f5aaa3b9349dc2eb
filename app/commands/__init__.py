"""One module per ``dolphinfit`` subcommand: ``add_arguments(parser)`` and ``run(args) -> int``."""
