"""Common settings of every picture the project writes (matplotlib): one resolution, unit labels."""

#: Resolution of every PNG written by the project (dots per inch).
DPI = 150
#: Micrometre label (the micro sign, not "um").
MICRO_M = "µm"
