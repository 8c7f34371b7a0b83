"""Write the generated part of motioncard/__init__.pyi from the built module: the enums'
members and one class per ErrorKind. Run after changing the SDK's ErrorKind list or the
register map's codes (`pip install ./python && python python/tools/stubs.py`);
tests/test_stubs.py fails while the stub differs."""

from __future__ import annotations

import pathlib
import sys

BEGIN = "# BEGIN GENERATED\n"
END = "# END GENERATED\n"
STUB = pathlib.Path(__file__).resolve().parent.parent / "motioncard" / "__init__.pyi"


def generated() -> str:
    import motioncard as mc

    out = []
    for name, doc in [
        ("AxisState", "PLCopen axis states."),
        ("GroupState", "PLCopen group states."),
        ("EventKind", "Event kinds."),
        ("Signal", "Scope signals."),
        ("StopCategory", "Stop categories."),
        ("StopReason", "Why an axis's last motion ended."),
    ]:
        out.append(f"class {name}(enum.IntEnum):\n")
        out.append(f'    """{doc}"""\n\n')
        for m in getattr(mc, name):
            out.append(f"    {m.name} = {m.value}\n")
        out.append("\n")
    for kind, cls, code, desc in mc.ERROR_KINDS:
        out.append(f"class {cls}(Error):\n")
        out.append(f'    """{kind} ({code}): {desc}"""\n\n')
    return "".join(out)


def stub_with(text: str, part: str) -> str:
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    return head + BEGIN + part + END + tail


if __name__ == "__main__":
    text = STUB.read_text()
    new = stub_with(text, generated())
    if "--check" in sys.argv[1:]:
        sys.exit(0 if new == text else 1)
    STUB.write_text(new)
