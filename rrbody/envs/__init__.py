"""Gymnasium environments on rrbody's table (placeholder while the package is built)."""
