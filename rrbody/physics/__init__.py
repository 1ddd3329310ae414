"""Physics layer: the effects and the compiled kernels they use (friction wrench, ICR quadrature, area tables)."""
