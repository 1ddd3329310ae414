"""Analysis layer: the ``simulate`` entry point, flip time, RR test, critical H, fits, sweeps, report."""
