"""What this machine offers the sandbox: Landlock (and which ABI), seccomp filters, libseccomp.

>>> isinstance(missing(), list)
True
"""

from __future__ import annotations

import os
import platform
from dataclasses import dataclass
from functools import cache

from crslab.sandbox import landlock, seccomp

ARCHITECTURES = ("x86_64", "aarch64")


@dataclass(frozen=True)
class Support:
    """The protections available here."""

    landlock_abi: int
    seccomp_filters: bool
    libseccomp: tuple[int, int, int] | None
    architecture: str

    @property
    def missing(self) -> list[str]:
        """One phrase per protection this machine lacks, each saying how to get it."""
        out = []
        if not os.uname().sysname == "Linux":
            return ["Linux (the sandbox uses Linux's Landlock and seccomp; on Windows use WSL 2)"]
        if self.architecture not in ARCHITECTURES:
            out.append(f"a supported processor ({self.architecture}; the sandbox knows "
                       f"{' and '.join(ARCHITECTURES)})")
        if self.landlock_abi < 1:
            out.append("Landlock (Linux 5.13 or later with Landlock enabled at boot: 'landlock' in "
                       "/sys/kernel/security/lsm, or lsm=landlock,... on the kernel command line)")
        if not self.seccomp_filters:
            out.append("seccomp filters (a kernel built with CONFIG_SECCOMP_FILTER)")
        if self.libseccomp is None:
            out.append("libseccomp (Debian and Ubuntu: apt install libseccomp2)")
        return out

    def summary(self) -> str:
        """One line for ``crslab doctor`` and the docs' troubleshooting."""
        if self.missing:
            return "sandbox unavailable: missing " + "; ".join(self.missing)
        tcp = "TCP refused" if self.landlock_abi >= 4 else "TCP not covered by Landlock (ABI < 4)"
        sig = "signals scoped" if self.landlock_abi >= 6 else "signals refused by seccomp only (ABI < 6)"
        lib = ".".join(map(str, self.libseccomp or ()))
        return (f"sandbox available: Landlock ABI {self.landlock_abi} ({tcp}, {sig}), seccomp, "
                f"libseccomp {lib}")


def _seccomp_filters() -> bool:
    try:
        with open("/proc/self/status") as f:
            return any(line.startswith("Seccomp:") for line in f)
    except OSError:
        return False


@cache
def support() -> Support:
    """This machine's :class:`Support` (probed once)."""
    if os.uname().sysname != "Linux":
        return Support(0, False, None, platform.machine())
    return Support(landlock_abi=landlock.abi_version(), seccomp_filters=_seccomp_filters(),
                   libseccomp=seccomp.version(), architecture=platform.machine())


def missing() -> list[str]:
    """What the sandbox needs and this machine lacks (empty: the sandbox works here)."""
    return support().missing
