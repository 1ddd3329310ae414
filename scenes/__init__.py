"""The scene scripts: one per paper figure or movie and per new question (run by name: `rrbody scene NAME`)."""
