"""Interactive exploration: the RTRI explorer with sliders (:mod:`.explorer`, :mod:`.explorer_figure`) and
Exudyn's 3-D renderer with wheels, rails, bridge deck, contact points and force arrows (:mod:`.view3d`;
:mod:`.screenshot` and :mod:`.headless` render frames without a screen).  Nothing here is imported by the rest of
the package; the modules import Exudyn and matplotlib only when used."""
