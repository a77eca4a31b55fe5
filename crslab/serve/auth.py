"""Who may use a ``crslab serve``: the roster, passwords, login cookies and per-user limits.

A roster is a CSV file with a header and one row per user::

    name,secret,role
    alice,pbkdf2_sha256$600000$3b1f...$9a0c...,student
    bob,token:Zq3...,student
    ta,pbkdf2_sha256$600000$...,admin

``secret`` is a password hash made by ``crslab serve --hash-password`` (PBKDF2-HMAC-SHA256, the
standard library's; the roster never holds a password) or ``token:`` and a random token (the
user types it as the password, or opens ``/?token=...``). ``role`` is ``student`` (default) or
``admin`` (may see the admin page).

A login gives a cookie signed with the server's secret (HMAC-SHA256): any replica that shares the
secret (``--secret-file``) accepts it, so a reverse proxy need not send a login back to the
replica that made it.

>>> h = hash_password("correct horse", salt=b"0123456789abcdef", iterations=1000)
>>> verify_secret(h, "correct horse"), verify_secret(h, "wrong")
(True, False)
>>> signer = CookieSigner(b"k" * 32)
>>> signer.user(signer.cookie("alice", now=100.0), now=200.0)
'alice'
>>> signer.user(signer.cookie("alice", now=100.0)[:-1] + "0", now=200.0) is None
True
"""

from __future__ import annotations

import base64
import csv
import hashlib
import hmac
import secrets
import time
from collections import deque
from collections.abc import Hashable
from dataclasses import dataclass
from pathlib import Path

PBKDF2_ITERATIONS = 600_000
"""OWASP's figure for PBKDF2-HMAC-SHA256 (2023)."""
COOKIE_LIFETIME_S = 12 * 3600.0
ROLES = ("student", "admin")


class RosterError(ValueError):
    """A roster file that cannot be used: one line naming the file, the row and the problem."""


@dataclass(frozen=True)
class User:
    """One roster row."""

    name: str
    secret: str
    role: str = "student"

    @property
    def admin(self) -> bool:
        return self.role == "admin"


def hash_password(password: str, *, salt: bytes | None = None, iterations: int = PBKDF2_ITERATIONS) -> str:
    """``pbkdf2_sha256$ITERATIONS$SALT$HASH`` (hex) for a roster."""
    salt = salt if salt is not None else secrets.token_bytes(16)
    digest = hashlib.pbkdf2_hmac("sha256", password.encode(), salt, iterations)
    return f"pbkdf2_sha256${iterations}${salt.hex()}${digest.hex()}"


def verify_secret(secret: str, given: str) -> bool:
    """Whether ``given`` (a password or a token) matches a roster secret (constant time).

    >>> verify_secret("token:abc", "abc"), verify_secret("token:abc", "abd")
    (True, False)
    """
    if secret.startswith("token:"):
        return hmac.compare_digest(secret[len("token:") :].encode(), given.encode())
    try:
        kind, iterations, salt, digest = secret.split("$")
        if kind != "pbkdf2_sha256":
            return False
        got = hashlib.pbkdf2_hmac("sha256", given.encode(), bytes.fromhex(salt), int(iterations))
    except ValueError:
        return False
    return hmac.compare_digest(got.hex(), digest)


def load_roster(path: Path) -> dict[str, User]:
    """The users of a roster file, by name; :class:`RosterError` for a bad file."""
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise RosterError(f"{path}: cannot read the roster ({exc.strerror})") from None
    rows = csv.DictReader(text.splitlines())
    if rows.fieldnames is None or not {"name", "secret"} <= set(rows.fieldnames):
        raise RosterError(f"{path}: the first line must name the columns: name,secret[,role]")
    users: dict[str, User] = {}
    for n, row in enumerate(rows, start=2):
        name, secret = (row.get("name") or "").strip(), (row.get("secret") or "").strip()
        role = (row.get("role") or "student").strip() or "student"
        if not name or not secret:
            raise RosterError(f"{path}: line {n}: a user needs a name and a secret")
        if not (
            secret.startswith("token:")
            and len(secret) > len("token:") + 7
            or secret.startswith("pbkdf2_sha256$")
            and secret.count("$") == 3
        ):
            raise RosterError(
                f"{path}: line {n}: {name}'s secret must be a password hash (crslab serve "
                "--hash-password) or token:TOKEN (at least 8 characters)"
            )
        if role not in ROLES:
            raise RosterError(f"{path}: line {n}: role must be {' or '.join(ROLES)}, got {role!r}")
        if name in users:
            raise RosterError(f"{path}: line {n}: {name} is listed twice")
        users[name] = User(name, secret, role)
    if not users:
        raise RosterError(f"{path}: the roster lists no user")
    return users


class CookieSigner:
    """Login cookies: ``name|expiry|HMAC``, signed with the server's secret key."""

    def __init__(self, key: bytes) -> None:
        self.key = key

    def _mac(self, body: str) -> str:
        return base64.urlsafe_b64encode(hmac.new(self.key, body.encode(), hashlib.sha256).digest()).decode()

    def cookie(self, name: str, *, now: float | None = None) -> str:
        """A cookie value for ``name`` valid for :data:`COOKIE_LIFETIME_S`."""
        expiry = int((now if now is not None else time.time()) + COOKIE_LIFETIME_S)
        body = f"{base64.urlsafe_b64encode(name.encode()).decode()}|{expiry}"
        return f"{body}|{self._mac(body)}"

    def user(self, cookie: str | None, *, now: float | None = None) -> str | None:
        """The user a cookie names, if it is genuine and not expired."""
        if not cookie or cookie.count("|") != 2:
            return None
        name_b64, expiry, mac = cookie.split("|")
        if not hmac.compare_digest(self._mac(f"{name_b64}|{expiry}"), mac):
            return None
        try:
            if int(expiry) < (now if now is not None else time.time()):
                return None
            return base64.urlsafe_b64decode(name_b64.encode()).decode()
        except ValueError:
            return None


class RateLimit:
    """At most ``count`` events per ``period_s`` (sliding window), e.g. compiles per minute.

    >>> r = RateLimit(2, 60.0)
    >>> r.allow(0.0), r.allow(1.0), r.allow(2.0), r.allow(61.0)
    (True, True, False, True)
    """

    def __init__(self, count: int, period_s: float) -> None:
        self.count = count
        self.period_s = period_s
        self.times: deque[float] = deque()

    def allow(self, now: float) -> bool:
        """Count one event at ``now`` if the limit allows it."""
        while self.times and self.times[0] <= now - self.period_s:
            self.times.popleft()
        if len(self.times) >= self.count:
            return False
        self.times.append(now)
        return True


def load_secret(path: Path | None) -> bytes:
    """The cookie key: the file's content (shared by replicas), else a fresh random key."""
    if path is None:
        return secrets.token_bytes(32)
    try:
        key = path.read_bytes().strip()
    except OSError as exc:
        raise RosterError(f"{path}: cannot read the secret ({exc.strerror})") from None
    if len(key) < 32:
        raise RosterError(
            f"{path}: the secret must be at least 32 bytes (e.g. openssl rand -hex 32 > {path})"
        )
    return key


class Backoff:
    """Wrong tries per key (a user's name, a client's address): the first ``free`` cost nothing,
    each one after shuts the key out for an exponential back-off, ``base_s`` doubling up to
    ``max_s``; never longer. A key with no wrong try for ``forget_s`` starts afresh. Times are the
    caller's clock (seconds; :func:`time.monotonic` in the server), so tests need no sleeps.

    A try is counted as wrong when it starts (:meth:`tried`), before the slow hash is checked, so
    many tries at once cannot all slip past the count; a right one is then :meth:`forgiven`.

    >>> b = Backoff(free=2, base_s=1.0, max_s=4.0)
    >>> for t in (0.0, 0.0, 0.0): b.tried("bob", t)
    >>> b.wait_s("bob", 0.5), b.wait_s("bob", 1.0)
    (0.5, 0.0)
    >>> b.tried("bob", 1.0); b.wait_s("bob", 1.0)
    2.0
    >>> for t in (3.0, 7.0, 11.0): b.tried("bob", t)
    >>> b.wait_s("bob", 11.0)
    4.0
    >>> b.forgiven("bob"); b.wait_s("bob", 11.0)
    0.0
    """

    def __init__(self, free: int, base_s: float, max_s: float, forget_s: float = 900.0) -> None:
        self.free = free
        self.base_s = base_s
        self.max_s = max_s
        self.forget_s = forget_s
        self._keys: dict[Hashable, tuple[int, float, float]] = {}
        """key: (wrong tries, when the last one came, until when the key is shut out)."""

    def delay_s(self, wrong: int) -> float:
        """How long ``wrong`` wrong tries in a row shut a key out.

        >>> [Backoff(3, 1.0, 30.0).delay_s(n) for n in (3, 4, 5, 6, 9, 40)]
        [0.0, 1.0, 2.0, 4.0, 30.0, 30.0]
        """
        if wrong <= self.free:
            return 0.0
        return min(self.max_s, self.base_s * 2.0 ** min(wrong - self.free - 1, 64))

    def _state(self, key: Hashable, now: float) -> tuple[int, float, float]:
        state = self._keys.get(key)
        if state is None or now - state[1] >= self.forget_s:
            return (0, now, now)
        return state

    def wait_s(self, key: Hashable, now: float) -> float:
        """How long ``key`` is still shut out (0: it may try now)."""
        return max(0.0, self._state(key, now)[2] - now)

    def tried(self, key: Hashable, now: float) -> None:
        """Count a try of ``key`` as wrong (call it once :meth:`wait_s` let the try in)."""
        wrong = self._state(key, now)[0] + 1
        self._keys[key] = (wrong, now, now + self.delay_s(wrong))
        if len(self._keys) > 100_000:  # an address-spraying client: drop the keys it has forgotten
            self._keys = {k: s for k, s in self._keys.items() if now - s[1] < self.forget_s}

    def forgiven(self, key: Hashable, *, entirely: bool = True) -> None:
        """The try was right: ``key`` starts afresh (``entirely``) or loses the one try counted."""
        state = self._keys.get(key)
        if state is None:
            return
        if entirely or state[0] <= 1:
            del self._keys[key]
        else:
            self._keys[key] = (state[0] - 1, state[1], state[2])


PAIR_BACKOFF = dict(free=5, base_s=1.0, max_s=30.0)
"""Wrong passwords for one name from one client address: 5 free, then 1 s, 2 s, 4 s, ... at most
30 s. Another address's guesses at that name never hold its owner back."""
ADDRESS_BACKOFF = dict(free=20, base_s=1.0, max_s=30.0)
"""Wrong passwords and tokens from one client address, whatever the name: 20 free (a class behind
one campus address mistypes), then the same back-off."""


class LoginLimits:
    """The back-offs a login passes: per client address (whatever names it tries) and per name and
    address pair. Wrong tries at a name from elsewhere never shut out the right password from an
    address that has not been guessing (a back-off per name did: 14 wrong tries from elsewhere kept
    a user's right password refused for 114 s).

    >>> limits, t = LoginLimits(), 0.0
    >>> for i in range(14): limits.tried("alice", "10.6.6.6", t)
    >>> limits.wait("alice", "10.6.6.6", t)
    (30.0, 'for this name from your address')
    >>> limits.wait("alice", "10.1.1.1", t)
    (0.0, '')
    """

    def __init__(self, pair: dict | None = None, address: dict | None = None) -> None:
        self.by_pair = Backoff(**(pair or PAIR_BACKOFF))
        self.by_address = Backoff(**(address or ADDRESS_BACKOFF))

    def wait(self, name: str, address: str, now: float) -> tuple[float, str]:
        """How long a login of ``name`` from ``address`` must still wait (0: it may try now), and
        whose limit holds it ("from your address", "for this name from your address")."""
        for wait, whose in ((self.by_address.wait_s(address, now), "from your address"),
                            (self.by_pair.wait_s((name, address), now), "for this name from your address")):
            if wait > 0:
                return wait, whose
        return 0.0, ""

    def tried(self, name: str, address: str, now: float) -> None:
        """Count a try (once :meth:`wait` let it in) as wrong until the slow hash proves it right:
        many tries at once cannot all slip past the count."""
        self.by_address.tried(address, now)
        self.by_pair.tried((name, address), now)

    def right(self, name: str, address: str) -> None:
        """The try was right: the pair starts afresh; the address loses the one try counted."""
        self.by_pair.forgiven((name, address))
        self.by_address.forgiven(address, entirely=False)
