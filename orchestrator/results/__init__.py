"""Stage 5, the results: a finished (or stopped) case read into tables and measures, and compared
with the analytical models and the study. Nothing here draws or writes reports."""
