"""Checks the wheel and sdist in DIR (``maturin build`` and ``maturin sdist``,
run by .ci/run) are what PyPI takes and what a user needs: a manylinux abi3
wheel that ``auditwheel show`` accepts, its extension stripped (no symbol
table, no DWARF), the licence texts in both, and the README as the long
description.

python python/tests/check_dist.py DIR"""

import re
import struct
import subprocess
import sys
import tarfile
import zipfile
from pathlib import Path

LICENCES = ("LICENSE-MIT", "LICENSE-APACHE")


def elf_sections(data):
    """The section names of a 64-bit little-endian ELF file."""
    if data[:4] != b"\x7fELF" or data[4] != 2 or data[5] != 1:
        raise ValueError("not a 64-bit little-endian ELF file")
    (shoff,) = struct.unpack_from("<Q", data, 0x28)
    shentsize, shnum, shstrndx = struct.unpack_from("<HHH", data, 0x3A)

    def header(i):
        base = shoff + i * shentsize
        (name,) = struct.unpack_from("<I", data, base)
        offset, size = struct.unpack_from("<QQ", data, base + 0x18)
        return name, offset, size

    _, str_off, str_size = header(shstrndx)
    strings = data[str_off : str_off + str_size]
    names = []
    for i in range(shnum):
        name = header(i)[0]
        names.append(strings[name : strings.index(b"\0", name)].decode())
    return names


def main(directory):
    problems = []
    wheels = sorted(directory.glob("*.whl"))
    sdists = sorted(directory.glob("*.tar.gz"))
    if len(wheels) != 1 or len(sdists) != 1:
        sys.exit(f"{directory}: expected one wheel and one sdist, found {wheels + sdists}")
    wheel, sdist = wheels[0], sdists[0]
    # PyPI's `laminar` is another project's: the distribution is laminar-brdf,
    # its import name laminar_brdf.
    if not wheel.name.startswith("laminar_brdf-") or not sdist.name.startswith("laminar_brdf-"):
        problems.append(f"{wheel.name}, {sdist.name}: not the distribution laminar-brdf")
    if not re.search(r"-cp\d+-abi3-manylinux_\d+_\d+_x86_64\.whl$", wheel.name):
        problems.append(f"{wheel.name}: not a manylinux abi3 wheel")
    shown = subprocess.run(
        [sys.executable, "-m", "auditwheel", "show", str(wheel)], capture_output=True, text=True
    )
    # auditwheel wraps its report at the terminal's width: compare words.
    if shown.returncode != 0 or "is consistent with" not in " ".join(shown.stdout.split()):
        problems.append(f"auditwheel show {wheel.name}: {shown.stdout}{shown.stderr}")
    with zipfile.ZipFile(wheel) as z:
        names = z.namelist()
        for so in (n for n in names if n.endswith(".so")):
            sections = elf_sections(z.read(so))
            left = [s for s in sections if s == ".symtab" or s.startswith(".debug_")]
            if left:
                problems.append(f"{so}: not stripped ({', '.join(left)})")
        if "laminar_brdf/__init__.py" not in names:
            problems.append(f"{wheel.name}: no package laminar_brdf")
        for licence in LICENCES:
            if not any(n.endswith(f".dist-info/licenses/{licence}") for n in names):
                problems.append(f"{wheel.name}: no {licence} in .dist-info/licenses")
        metadata = z.read(next(n for n in names if n.endswith(".dist-info/METADATA"))).decode()
        if "Description-Content-Type: text/markdown" not in metadata or "Mitsuba 3" not in metadata:
            problems.append(f"{wheel.name}: METADATA has no long description (python/README.md)")
    with tarfile.open(sdist) as t:
        members = t.getnames()
        for licence in LICENCES:
            if not any(m.endswith(f"/{licence}") for m in members):
                problems.append(f"{sdist.name}: no {licence}")
    for p in problems:
        print(f"check_dist: {p}", file=sys.stderr)
    if problems:
        sys.exit(1)
    print(f"check_dist: {wheel.name} ({wheel.stat().st_size} B) and {sdist.name} ({sdist.stat().st_size} B): "
          "manylinux abi3 (auditwheel), stripped, licences, long description")


if __name__ == "__main__":
    main(Path(sys.argv[1]))
