"""fredholm-ray: one Fredholm render split into sample ranges, rendered as Ray tasks, merged with fredholm merge."""
__version__ = "0.1.0"
