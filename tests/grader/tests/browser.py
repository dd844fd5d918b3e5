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


def colour_box(picture, hex_colour):
    """(left, top, right, bottom) pixel bounds of a colour in a PNG, or None where it is absent."""
    from PIL import Image
    wanted = rgb(hex_colour)
    with Image.open(picture) as image:
        pixels = image.convert("RGB")
        mask = Image.new("L", pixels.size)
        mask.putdata([255 if pixel == wanted else 0 for pixel in pixels.getdata()])
    return mask.getbbox()


def blank_rows(picture, share):
    """Whether the bottom `share` of a PNG's rows is all white (nothing cut off there)."""
    from PIL import Image
    with Image.open(picture) as image:
        rgb_image = image.convert("RGB")
        width, height = rgb_image.size
        bottom = rgb_image.crop((0, height - max(1, int(share * height)), width, height))
        return all(colour == (255, 255, 255) for _, colour in bottom.getcolors(maxcolors=1 << 22))
