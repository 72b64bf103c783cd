"""Stage 6, the report: plots, previews and Markdown pages from the results, and post_case, which
writes a case's results folder."""
