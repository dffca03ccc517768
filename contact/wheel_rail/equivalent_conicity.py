"""The equivalent-conicity formulas live in :mod:`contact.geometry.conicity`; this name is kept for the wear
loop's import (:mod:`contact.wear.conicity`)."""

from contact.geometry.conicity import harmonic_conicity

__all__ = ["harmonic_conicity"]
