"""Reproduce the paper's analyses: each section module exposes ``run(out_dir, quiet) -> list[str]``.

The returned strings are Markdown lines for the summary; figures are written into
``out_dir``.
"""
