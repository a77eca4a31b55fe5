"""``crslab serve``: the whole lab bench as a web page (docs/serve.md)."""

from __future__ import annotations

import argparse
import gc
import getpass
import ipaddress
import secrets
import socket
import sys
from pathlib import Path

from crslab.cli import CliError

DEFAULT_PORT = 8446


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``serve`` subcommand."""
    p = sub.add_parser(
        "serve",
        help="serve the lab bench (editor, Tera Term, the arm in 3D, scopes, variables) as a web page",
        description="Serve crslab as a web page: a C editor holding the lab, Run and Stop, Tera Term, "
        "the arm in 3D (drag a link to push it), scopes and watched variables, for any browser. Every run "
        "is crslab sim's, sandboxed and paced on this machine; the browser runs no student code. Without "
        "--users it serves you alone, on this machine, at the URL it prints.",
    )
    p.add_argument(
        "--host",
        default="127.0.0.1",
        help="address to listen on (default: %(default)s; another needs --users)",
    )
    p.add_argument(
        "--port", type=int, default=DEFAULT_PORT, help="TCP port (default: %(default)s; 0 picks a free one)"
    )
    p.add_argument(
        "--users",
        type=Path,
        metavar="ROSTER.csv",
        help="serve the users of this roster (name,secret[,role]) with a login and per-user limits",
    )
    p.add_argument(
        "--max-sessions",
        type=int,
        default=200,
        metavar="N",
        help="page sessions at once, every user together (default: %(default)s)",
    )
    p.add_argument(
        "--max-sessions-per-user",
        type=int,
        default=2,
        metavar="N",
        help="page sessions one user may hold at once (default: %(default)s)",
    )
    p.add_argument(
        "--compiles-per-minute",
        type=int,
        default=6,
        metavar="N",
        help="builds, runs and checks a user may start per minute, one at a time (default: %(default)s)",
    )
    p.add_argument(
        "--max-run-s",
        type=float,
        default=600.0,
        metavar="SECONDS",
        help="the longest run, in simulated seconds (default: %(default)g)",
    )
    p.add_argument(
        "--mem-limit-mb",
        type=int,
        default=1024,
        metavar="MB",
        help="memory limit of a check's lab process (default: %(default)s; a run's firmware has its "
        "WebAssembly memory)",
    )
    p.add_argument(
        "--check-cpu-s",
        type=float,
        default=60.0,
        metavar="SECONDS",
        help="CPU time a page's golden-file check may use (default: %(default)g)",
    )
    p.add_argument(
        "--check-wall-s",
        type=float,
        default=120.0,
        metavar="SECONDS",
        help="wall time a page's golden-file check may take; past it, it ends where it got to "
        "(default: %(default)g)",
    )
    p.add_argument(
        "--secret-file",
        type=Path,
        metavar="FILE",
        help="the key login cookies are signed with (at least 32 bytes), shared by replicas behind "
        "one proxy (default: a fresh key, so logins end when the server stops)",
    )
    p.add_argument(
        "--forwarded-allow-ips",
        default="127.0.0.1",
        metavar="IPS",
        help="reverse proxies whose X-Forwarded-* headers are trusted (default: %(default)s)",
    )
    p.add_argument(
        "--hash-password",
        action="store_true",
        help="read a password (twice, without echo; or one line on a pipe) and print its hash for a "
        "roster, then exit",
    )
    p.set_defaults(func=run_serve)


def _loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def _hash_password() -> int:
    from crslab.serve.auth import hash_password

    if sys.stdin.isatty():
        first = getpass.getpass("password: ")
        if getpass.getpass("again: ") != first:
            raise CliError("the two passwords differ")
    else:
        first = sys.stdin.readline().rstrip("\n")
    if len(first) < 8:
        raise CliError("a password needs at least 8 characters")
    print(hash_password(first))
    return 0


def _listen(host: str, port: int) -> socket.socket:
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind((host, port))
    except OSError as exc:
        sock.close()
        hint = "; another server uses it (--port 0 picks a free one)" if port else ""
        raise CliError(f"cannot listen on {host}:{port} ({exc.strerror}){hint}") from None
    sock.listen(511)
    sock.set_inheritable(False)
    return sock


def run_serve(args: argparse.Namespace) -> int:
    """``crslab serve``."""
    if args.hash_password:
        return _hash_password()
    from crslab.sandbox import missing as sandbox_missing
    from crslab.serve.auth import CookieSigner, RosterError, load_roster, load_secret

    if args.users is None and not _loopback(args.host):
        raise CliError(
            f"without --users crslab serve serves only this machine; --host {args.host} would let "
            "anyone reach it: give a roster (--users roster.csv), or leave --host out"
        )
    for name in ("max_sessions", "max_sessions_per_user", "compiles_per_minute"):
        if getattr(args, name) < 1:
            raise CliError(f"--{name.replace('_', '-')} must be at least 1")
    for name in ("max_run_s", "check_cpu_s", "check_wall_s"):
        if not getattr(args, name) > 0:
            raise CliError(f"--{name.replace('_', '-')} must be > 0")
    try:
        roster = load_roster(args.users) if args.users is not None else None
        signer = CookieSigner(load_secret(args.secret_file))
    except RosterError as exc:
        raise CliError(str(exc)) from None
    lacking = sandbox_missing()
    if lacking and roster is not None:
        raise CliError(
            f"the sandbox cannot run on this machine (it lacks {'; '.join(lacking)}): crslab serve "
            "runs other people's labs only inside it"
        )
    if lacking:
        print(
            "crslab serve: warning: running labs without the sandbox: this machine lacks "
            + "; ".join(lacking),
            file=sys.stderr,
        )

    import uvicorn

    from crslab.serve.app import ServeSettings, make_app
    from crslab.serve.page_process import SessionLimits
    from crslab.serve.page_sessions import Sessions, UserLimits

    sessions = Sessions(
        UserLimits(compiles_per_minute=args.compiles_per_minute, max_sessions=args.max_sessions,
                   max_sessions_per_user=args.max_sessions_per_user),
        SessionLimits(max_run_s=args.max_run_s, memory_mb=args.mem_limit_mb, check_cpu_s=args.check_cpu_s,
                      check_wall_s=args.check_wall_s, sandboxed=not lacking),
    )
    token = secrets.token_urlsafe(16)
    app = make_app(ServeSettings(roster, signer, local_token=token), sessions)
    sock = _listen(args.host, args.port)
    host, port = sock.getsockname()[:2]
    shown = f"[{host}]" if ":" in host else host
    from crslab.serve.page_sessions import session_context

    session_context()  # the fork server imports crslab now, before the first page asks for a session
    if roster is None:
        print(
            f"crslab serve: open http://{shown}:{port}/?token={token} in your browser (Ctrl-C stops the "
            "server)",
            file=sys.stderr,
            flush=True,
        )
    else:
        print(
            f"crslab serve: serving {len(roster)} users on http://{shown}:{port}/ (Ctrl-C stops the server)",
            file=sys.stderr,
            flush=True,
        )
    config = uvicorn.Config(
        app,
        log_level="warning",
        ws="websockets-sansio",
        ws_max_size=2_000_000,
        # no per-message deflate: a chunk's scope rows are float32 that deflate shrinks by a quarter
        # for half a millisecond of the event loop each (docs/serve.md, Capacity)
        ws_per_message_deflate=False,
        proxy_headers=True,
        forwarded_allow_ips=args.forwarded_allow_ips,
        lifespan="off",
    )
    server = uvicorn.Server(config)
    gc.freeze()  # what the imports made lives as long as the server: a full collection skips it
    try:
        server.run(sockets=[sock])
    finally:
        for session in sessions.all():
            sessions.close(session)
        sock.close()
    print("crslab serve: stopped", file=sys.stderr)
    return 0
