"""The server's pictures (SVG documents) as values a notebook shows inline and a script saves."""

from __future__ import annotations

__all__ = ["Picture"]


class Picture(str):
    """An SVG document: a str, shown as the picture by Jupyter (_repr_svg_); save(path) writes it."""

    def _repr_svg_(self) -> str:
        return str(self)

    def save(self, path: str) -> str:
        with open(path, "w", encoding="utf-8") as f:
            f.write(self)
        return path
