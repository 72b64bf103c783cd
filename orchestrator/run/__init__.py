"""Stage 4, the run: the solver driven in watched segments, its health, contacts and floating bodies,
stops and resumes, and run.json."""
