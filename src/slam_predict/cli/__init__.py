"""The ``slam-predict`` command line: one module per subcommand (``parser`` + ``run``)."""
