"""Ready-made cases (the RTRI validation case and others); their unpublished inputs live in one place each,
e.g. :class:`exudyn_wheelrail.scenarios.rtri_assumptions.RtriAssumptions`."""
