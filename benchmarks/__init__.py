"""Work-precision benchmarks and speed targets for rrbody.

Run ``python -m benchmarks.run`` (``make bench``) from the repository root; results go to
``benchmarks/results/`` (CSV, PNG and ``SUMMARY.md``). See ``benchmarks/README.md``.
"""
