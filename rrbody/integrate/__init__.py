"""Integration layer: the stepping loop, its methods and the event detector."""
