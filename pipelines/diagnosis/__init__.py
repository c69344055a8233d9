"""Sim-to-real gap diagnosis (``roadscan diagnose``).

Where a model and a measurement disagree, which unmodelled effect causes it, and how much
adding that effect closes the gap. One idea per module:

- :mod:`.measured`   reading a measured mu(v) CSV (per-row temperature, load, condition)
- :mod:`.gap`        the gap metric (rms of log10 real/sim), noise estimate, significance,
                     gap per speed band
- :mod:`.model`      the simulation specification that effects modify, and its evaluation
                     with the friction engine at the measured speeds only
- :mod:`.effects`    the plug-in registry; one module per unmodelled effect
- :mod:`.search`     the candidates (singles, greedy pairs, calibration + each effect), ranked
- :mod:`.fitting`    one bounded least-squares fit (cold or warm starts, shared cache, refusal)
- :mod:`.cv`         the held-out third (20 points or more); shrink, interval, score
- :mod:`.search_few`, :mod:`.few`, :mod:`.evidence`  fewer than 20 points: Bayesian
                     model comparison (Laplace evidence), PRESS residuals
- :mod:`.equivalence` an effect the uncertain inputs beyond their ranges reproduce is them
- :mod:`.same_physics` an effect that is an input continued (fine roughness and q1, load and
                     sigma0, temperature offset and T0) is named once, with the input value
- :mod:`.next_measurement` where the two most probable explanations differ most
- :mod:`.stats`      multi-start bounded least squares, Jacobian, Gauss-Newton covariance
- :mod:`.calibration` uncertain inputs (``--uncertain``, the default q1 range) as a pseudo-effect
- :mod:`.verdict`    effect / calibration / inconclusive / null, confidence, plausibility
- :mod:`.provenance` the ``inputs`` of diagnosis.json (values, files with sha256, assumed)
- :mod:`.curves`     dense-grid curves of the report (band of the uncertain inputs, corrected)
- :mod:`.joint`      several measurements (``--measurements``) with a joint calibration
- :mod:`.run_command` the command-line side (provenance hints, surface loading, --measurements)
- :mod:`.bandmap`    which length scales and frequencies carry mu in each speed band
- :mod:`.surface`    the surface level (scan versus its fitted Gaussian self-affine twin)
- :mod:`.cases`      the seeded case generator used for the proof (tests and benchmark)
- :mod:`.report`     diagnosis.json and report.html (:mod:`.report_joint` for several measurements)
"""
