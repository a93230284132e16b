"""Campaign report: one self-contained HTML page about a collection campaign (``slam-predict
report``): :mod:`campaign` reads it, :mod:`sections` and :mod:`models` / :mod:`predictions` build
the parts, :mod:`figures` draws, :mod:`html` renders, :mod:`build` assembles and writes."""
