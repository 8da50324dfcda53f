"""What the scripts that regenerate parts of docs/ share: markdown tables, byte counts, a line on
the machine, and rewriting the part of a page between <!-- NAME: begin --> and <!-- NAME: end -->
(written to a temporary file, then renamed, so a failure leaves the page as it was)."""

import os
import platform


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(str(cell) for cell in row) + " |" for row in rows]
    return "\n".join(lines)


def fmt_bytes(x):
    if x < 0:
        return "n/a"
    for unit, scale in (("MiB", 2**20), ("KiB", 2**10)):
        if x >= scale:
            return f"{x / scale:.2f} {unit}"
    return f"{x:.0f} B"


def machine():
    """CPU count and model, and the OS; no load average, so that regenerating a section from the
    same results changes nothing (callers that want the load say so in their own words)."""
    model = ""
    try:
        with open("/proc/cpuinfo") as f:
            model = next((line.split(":", 1)[1].strip() for line in f if line.startswith("model name")), "")
    except OSError:
        pass
    return f"{os.cpu_count()} CPUs ({model or platform.processor()}), {platform.system()} {platform.release()}"


def markers(name):
    return f"<!-- {name}: begin -->", f"<!-- {name}: end -->"


def replace_sections(page, sections, heading_if_absent=None):
    """Rewrites each section {name: body} of page between its markers. A section whose markers
    are missing is appended under heading_if_absent[name] when given, else it is an error."""
    try:
        with open(page) as f:
            text = f.read()
    except OSError as e:
        raise SystemExit(f"{page}: cannot read ({e.strerror})")
    for name, body in sections.items():
        begin, end = markers(name)
        block = f"{begin}\n{body}\n{end}"
        if begin in text and end in text:
            text = text[:text.index(begin)] + block + text[text.index(end) + len(end):]
        elif heading_if_absent and name in heading_if_absent:
            text = text.rstrip("\n") + f"\n\n{heading_if_absent[name]}\n\n{block}\n"
        else:
            raise SystemExit(f"{page}: no {begin} ... {end} markers")
    temporary = page + ".tmp"
    with open(temporary, "w") as f:
        f.write(text)
    os.replace(temporary, page)
