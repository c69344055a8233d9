"""The computing commands of ``roadscan``: one module per command (``NAME``, ``HELP``,
``add_arguments(parser)``, ``run(args) -> int``), each listed in ``COMMAND_MODULES`` of
:mod:`pipelines.cli.app`."""
