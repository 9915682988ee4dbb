"""From measurements to results: fits of <dJ^2>(dt), MD against theory, and the figures."""
