"""``--model auto``: the one-mechanism model (``rock``) while its mechanism is admissible, the
multi-block simulation (``simulate``) from the first violation, and back at rest or on a mechanism
(:mod:`.model`); the map between a mechanism and the bodies' state (:mod:`.manifold`)."""
from .manifold import bodies_state, mechanism_of
from .model import AutoModel, AutoResult, Segment

__all__ = ["AutoModel", "AutoResult", "Segment", "bodies_state", "mechanism_of"]
