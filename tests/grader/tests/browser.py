"""A page as Debian's headless chromium draws it, for the grader's tests of the pages they write
(the class report, a submission's report.html): a screenshot, and the colours in it."""

import subprocess
from pathlib import Path


def screenshot(page, width=1000, height=2400, timeout=300):
    """Draws the HTML file `page` in headless chromium into a PNG beside it; returns (the PNG's
    path, or None if chromium drew nothing, and chromium's output)."""
    picture = Path(page).with_suffix(".png")
    picture.unlink(missing_ok=True)
    done = subprocess.run(["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                           f"--screenshot={picture}", f"--window-size={width},{height}", Path(page).as_uri()],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=timeout)
    return (picture if picture.is_file() else None), done.stdout


def colour_counts(picture):
    """{(r, g, b): pixels} of a PNG."""
    from PIL import Image
    with Image.open(picture) as image:
        colours = image.convert("RGB").getcolors(maxcolors=1 << 22)
    return {colour: count for count, colour in colours}


def rgb(hex_colour):
    """(r, g, b) of "#rrggbb"."""
    return tuple(int(hex_colour[k:k + 2], 16) for k in (1, 3, 5))
