"""A ROS message through the wire, as a subscriber receives it (for the conversion tests)."""
from __future__ import annotations

import io


def wire(msg, cls=None):
    """Serialise ``msg`` and deserialise it into a new ``cls`` (default: the message's own
    type); float32 fields lose precision here, as on a real topic."""
    buffer = io.BytesIO()
    msg.serialize(buffer)
    out = (cls or type(msg))()
    out.deserialize(buffer.getvalue())
    return out
