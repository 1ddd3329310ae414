"""Validated plain data: bodies, drive, friction laws, scene, trajectory, checks, io, optional extras."""
