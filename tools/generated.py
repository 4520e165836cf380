"""Shared by the generators in tools/: write a generated file, or with --check on the command
line only compare it with the committed one (the ctest `generator.*_up_to_date` tests)."""
import sys


def write_or_check(target, text, generator):
    """Writes `text` to `target`, or compares under --check. Returns the process exit status."""
    if "--check" in sys.argv[1:]:
        if not target.exists() or target.read_text() != text:
            print(f"{target} is out of date: run {generator}", file=sys.stderr)
            return 1
        print(f"{target} is up to date")
        return 0
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_text(text)
    print(f"wrote {target}")
    return 0
