"""The records of a `descent study` folder, for the tools that read them:
study.csv, or study.csv.gz where a long study was archived compressed in
bench/results."""
import csv
import gzip


def read_study(folder):
    """The rows of folder/study.csv (or study.csv.gz) as dicts; [] when the
    folder holds neither."""
    for name, opener in (("study.csv", open), ("study.csv.gz", gzip.open)):
        if (folder / name).exists():
            with opener(folder / name, "rt") as f:
                return list(csv.DictReader(f))
    return []
