"""Model layer (bottom): validated plain data: bodies, drive, friction laws, scene, trajectory, checks, I/O."""
