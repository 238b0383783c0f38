#!/usr/bin/python3
"""Checks that the benchmark tables quoted in the documents are the ones the benchmark scripts
last wrote to bench/output/ (the documents copy them by hand after a run: this catches a copy
that was forgotten or edited). Each pair below names a document and an output file; every
Markdown table of the output file (a block of lines starting with '|'), or the ones listed by
position, must appear in the document line for line. Exit 1 with the tables that do not.

Usage (from the repository root): /usr/bin/python3 scripts/check_bench_tables.py"""
import sys

# (document, output file, positions of the output's tables to find, None: all)
PAIRS = [
    ("docs/performance.md", "bench/output/like_for_like.md", None),
    ("docs/performance.md", "bench/output/trial.md", None),
    ("docs/performance.md", "bench/output/scaling.md", None),
    ("docs/performance.md", "bench/output/controller.md", None),
    ("docs/performance.md", "bench/output/jobs.md", None),
    ("docs/performance.md", "bench/output/model.md", None),
    ("docs/continuation.md", "bench/output/continuation.md", None),
    ("docs/nonsmooth.md", "bench/output/switching.md", None),
]


def tables(text):
    """The Markdown tables of a text, each as a tuple of its lines."""
    found, block = [], []
    for line in text.split("\n") + [""]:
        if line.startswith("|"):
            block.append(line.rstrip())
        elif block:
            found.append(tuple(block))
            block = []
    return found


def main():
    failures = 0
    for doc, output, positions in PAIRS:
        in_doc = set(tables(open(doc, encoding="utf-8").read()))
        produced = tables(open(output, encoding="utf-8").read())
        if not produced:
            print(f"{output}: no table")
            failures += 1
            continue
        for k in positions if positions is not None else range(len(produced)):
            if produced[k] not in in_doc:
                print(f"{doc} does not quote table {k} of {output}:")
                print("\n".join(produced[k]))
                failures += 1
    if failures:
        print(f"{failures} table(s) differ: copy them from bench/output/ into the documents")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
