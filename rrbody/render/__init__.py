"""Renderers: off-screen MP4 (:mod:`rrbody.render.mp4`) and rerun recordings (:mod:`rrbody.render.rerun`)."""
