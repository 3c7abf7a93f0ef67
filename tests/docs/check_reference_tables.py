#!/usr/bin/env python3
"""The reference tables of the docs list everything the code has.

- docs/operations.md's metrics table names every metric the service exposes: each
  `# HELP caustic_...` line written in server/ (the exposition is written there by hand).
- docs/http-api.md's errors table has a row for every status that the OpenAPI document
  (server/http/openapi.json) gives for an error (4xx and 5xx).
Exit code 1 and one line per thing missing.

usage: check_reference_tables.py REPO_ROOT
"""
import json
import re
import sys
from pathlib import Path


def table_cells(page, heading):
    """The first cells of the rows of the first table under `## heading` in `page`."""
    text = page.read_text(encoding="utf-8")
    section = text.split(f"\n## {heading}\n", 1)[1].split("\n## ", 1)[0]
    return [row.split("|")[1].strip() for row in section.splitlines()
            if row.startswith("|") and not row.startswith("|---")]


def main():
    root = Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    missing = []

    metrics = set()
    for source in sorted((root / "server").glob("**/*.cpp")):
        metrics.update(re.findall(r"# HELP (caustic_\w+)", source.read_text(encoding="utf-8")))
    documented = {re.match(r"`(caustic_\w+)", c).group(1)
                  for c in table_cells(root / "docs/operations.md", "Metrics")
                  if c.startswith("`caustic_")}
    missing += [f"docs/operations.md, Metrics: no row for {m}" for m in sorted(metrics - documented)]
    missing += [f"docs/operations.md, Metrics: {m} is exposed by nothing in server/"
                for m in sorted(documented - metrics)]

    api = json.loads((root / "server/http/openapi.json").read_text(encoding="utf-8"))
    statuses = {code for ops in api["paths"].values() for op in ops.values()
                if isinstance(op, dict) for code in op.get("responses", {}) if code[0] in "45"}
    rows = set(table_cells(root / "docs/http-api.md", "Errors"))
    missing += [f"docs/http-api.md, Errors: no row for {s}, which the OpenAPI document gives"
                for s in sorted(statuses - rows)]

    for line in missing:
        print(line)
    print(f"check_reference_tables: {len(metrics)} metrics, {len(statuses)} error statuses, "
          f"{len(missing)} missing")
    sys.exit(1 if missing else 0)


if __name__ == "__main__":
    main()
