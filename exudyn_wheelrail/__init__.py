"""exudyn-wheelrail: wheel-rail contact for Exudyn."""
