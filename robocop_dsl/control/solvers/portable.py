"""Loading proxsuite's portable build, so that a run repeats bit for bit.

proxsuite ships three builds of its bindings and loads the widest one the processor
runs (AVX-512, AVX2, else the portable SSE2 one). With AVX2 and AVX-512 the last bits
of a ProxQP answer depend on how its work memory happens to be aligned, which the heap
decides: the same program solved twice, in one process or two, can give commands
differing by 1e-12 rad/s, and runs that drift apart from there. The portable build
answers the same program the same way every time, and on the controller's programs
(tens of variables) it is as fast (``bench/controller_cycle.py``).
"""

from __future__ import annotations

import sys
import types

_SCALAR = types.SimpleNamespace(has_AVX512F=lambda: False, has_AVX2=lambda: False)


def portable_proxsuite():
    """The ``proxsuite`` module, its portable build loaded if it was not imported
    before (then the build already loaded stays)."""
    if "proxsuite" in sys.modules:
        return sys.modules["proxsuite"]
    real = sys.modules.get("proxsuite.instructionset")
    sys.modules["proxsuite.instructionset"] = _SCALAR
    try:
        import proxsuite
    finally:
        if real is None:
            del sys.modules["proxsuite.instructionset"]
        else:
            sys.modules["proxsuite.instructionset"] = real
    return proxsuite

