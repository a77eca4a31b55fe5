"""The web application of ``crslab serve`` (Starlette, served by uvicorn).

Routes: ``/`` the page (``static/index.html``), ``/static/...`` its scripts, styles and vendored
libraries, ``/api/login`` and ``/api/logout``, ``/api/me``, ``/api/template`` (``crslab new``'s
starting file for a lab and a generation), ``/api/scenarios``, ``/api/arm`` (the arm's shapes from the
MuJoCo model, for the 3D view), ``/api/download/{kind}`` (the last run's transcript, CSV or
``.rrd``), ``/admin`` (sessions, for admins) and ``/ws``, one WebSocket per page session
(:mod:`crslab.serve.page_messages`).

Who is who: without a roster the server serves one user on this machine, who proves it by the
token in the URL ``crslab serve`` printed (the page then keeps a cookie); with a roster, a login.
Either way a signed cookie (:class:`crslab.serve.auth.CookieSigner`) names the user on every
request and on the WebSocket, whose ``Origin`` must be the page's own.
"""

from __future__ import annotations

import asyncio
import html
import json
import secrets
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING
from urllib.parse import urlparse

from starlette.applications import Starlette
from starlette.requests import Request
from starlette.responses import FileResponse, HTMLResponse, JSONResponse, RedirectResponse, Response
from starlette.routing import Mount, Route, WebSocketRoute
from starlette.staticfiles import StaticFiles
from starlette.websockets import WebSocket, WebSocketDisconnect, WebSocketDisconnected

from crslab.framework_facts import TICKS_PER_S
from crslab.generations import GENERATIONS, NEWEST
from crslab.run.status import RunStatus
from crslab.serve import wire
from crslab.serve.auth import CookieSigner, LoginLimits, User, verify_secret
from crslab.serve.page_messages import ProtocolError, parse_message
from crslab.serve.page_sessions import LimitError, PageSession, Sessions
from crslab.serve.run_host import DOWNLOADS
from crslab.starters import LABS, starter_text

if TYPE_CHECKING:
    import numpy as np

STATIC = Path(__file__).parent / "static"
COOKIE = "crslab_session"
USER_COOKIE = "crslab_user"
"""The user's name, not secret: a reverse proxy keeps each user on one replica by it."""
LOCAL_USER = "you"
RUN_COMMANDS = ("stop", "speed", "vars", "hand", "release")
"""What the page says to its running lab: its run host gets them."""
SESSION_GONE = wire.ended(RunStatus.CRASHED, "crslab's session process ended unexpectedly")
"""What the page is told when its session process ended during a build, run or check."""
CSP = (
    "default-src 'self'; script-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' data: blob:; "
    "connect-src 'self'; frame-ancestors 'none'; base-uri 'none'; form-action 'self'"
)


@dataclass
class ServeSettings:
    """How the server admits users: a roster (None: one local user with ``local_token``)."""

    roster: dict[str, User] | None
    signer: CookieSigner
    local_token: str = ""


class CrsServer:
    """The server's state and its request handlers (``clock``: seconds, for the login limits)."""

    def __init__(self, settings: ServeSettings, sessions: Sessions,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.settings = settings
        self.sessions = sessions
        self.clock = clock
        self._limits = LoginLimits()
        self._scenarios: list[dict] | None = None
        self._arm: dict[str, dict] = {}

    # -- who is asking ------------------------------------------------------------------------
    def user_of(self, cookies: dict[str, str]) -> str | None:
        name = self.settings.signer.user(cookies.get(COOKIE))
        if name is None:
            return None
        if self.settings.roster is None:
            return name if name == LOCAL_USER else None
        return name if name in self.settings.roster else None

    def is_admin(self, user: str) -> bool:
        roster = self.settings.roster
        return roster is None or (user in roster and roster[user].admin)

    def _logged_in(self, response: Response, request: Request, user: str) -> Response:
        secure = request.url.scheme == "https"
        response.set_cookie(
            COOKIE,
            self.settings.signer.cookie(user),
            httponly=True,
            samesite="strict",
            secure=secure,
            max_age=12 * 3600,
        )
        response.set_cookie(USER_COOKIE, user, samesite="strict", secure=secure, max_age=12 * 3600)
        return response

    # -- pages ------------------------------------------------------------------------------
    async def index(self, request: Request) -> Response:
        token = request.query_params.get("token")
        if token is not None:  # the URL crslab serve printed, or a roster user's token link
            address, now = _address(request), self.clock()
            wait = self._limits.by_address.wait_s(address, now)
            if wait > 0:
                return _too_many(f"too many wrong tokens or passwords from your address; try again in "
                                 f"{_seconds(wait)}", wait, html_page=True)
            self._limits.by_address.tried(address, now)  # a wrong token until it proves right
            user = self._token_user(token)
            if user is not None:
                self._limits.by_address.forgiven(address, entirely=False)
                return self._logged_in(RedirectResponse("/", status_code=303), request, user)
        response = FileResponse(
            STATIC / "index.html", headers={"Content-Security-Policy": CSP, "Cache-Control": "no-store"}
        )
        return response

    def _token_user(self, token: str) -> str | None:
        roster = self.settings.roster
        if roster is None:
            ok = secrets.compare_digest(token.encode(), self.settings.local_token.encode())
            return LOCAL_USER if ok else None
        return next(
            (
                u.name
                for u in roster.values()
                if u.secret.startswith("token:") and verify_secret(u.secret, token)
            ),
            None,
        )

    async def login(self, request: Request) -> Response:
        try:
            body = await request.json()
            name, password = str(body["name"]), str(body["password"])
        except (ValueError, KeyError, TypeError):
            return JSONResponse({"error": 'send {"name": ..., "password": ...}'}, status_code=400)
        roster = self.settings.roster
        if roster is None:
            return JSONResponse(
                {"error": "this server has no logins: open the URL crslab serve printed"}, status_code=400
            )
        # the limits, checked before the slow hash: per client address (whatever the names it
        # tries) and per name and address pair (guesses from elsewhere never hold the name's owner
        # back), each an exponential back-off
        address, now = _address(request), self.clock()
        wait, whose = self._limits.wait(name, address, now)
        if wait > 0:
            return _too_many(f"too many wrong passwords {whose}; try again in {_seconds(wait)}", wait)
        self._limits.tried(name, address, now)  # counted as wrong now: tries at once cannot slip past
        user = roster.get(name)
        # the hash is checked even for an unknown name, so the time taken does not tell names apart
        secret = user.secret if user is not None else "pbkdf2_sha256$600000$00$00"
        # PBKDF2 takes a core for about half a second: in a thread (hashlib lets go of the GIL), so
        # the relay of every running session goes on meanwhile
        if not await asyncio.to_thread(verify_secret, secret, password) or user is None:
            return JSONResponse({"error": "wrong name or password"}, status_code=401)
        self._limits.right(name, address)
        return self._logged_in(JSONResponse({"user": name}), request, name)

    async def logout(self, request: Request) -> Response:
        response = JSONResponse({"user": None})
        response.delete_cookie(COOKIE)
        response.delete_cookie(USER_COOKIE)
        return response

    async def me(self, request: Request) -> Response:
        user = self.user_of(request.cookies)
        if user is None:
            return JSONResponse({"user": None, "login": self.settings.roster is not None}, status_code=401)
        limits = self.sessions.limits
        return JSONResponse(
            {
                "user": user,
                "admin": self.is_admin(user),
                "login": self.settings.roster is not None,
                "limits": {
                    "compiles_per_minute": limits.compiles_per_minute,
                    "max_run_s": self.sessions.run_limits.max_run_s,
                },
                "labs": LABS,
                "generations": {g.name: g.title.removeprefix("the ") for g in GENERATIONS},
                "generation_headers": {g.name: g.include for g in GENERATIONS},
                "default_generation": NEWEST.name,  # what crslab new writes without --gen
            }
        )

    async def template_text(self, request: Request) -> Response:
        if self.user_of(request.cookies) is None:
            return JSONResponse({"error": "log in first"}, status_code=401)
        lab, gen = request.query_params.get("lab", "lab1"), request.query_params.get("gen", "A")
        try:
            text = starter_text(lab, gen)
        except ValueError as exc:
            return JSONResponse({"error": str(exc)}, status_code=404)
        return JSONResponse({"name": f"{lab}.c", "text": text})

    async def scenarios(self, request: Request) -> Response:
        if self._scenarios is None:
            from crslab.scenario.load import DEFAULT_SCENARIO, builtin_names, load_scenario

            names = [DEFAULT_SCENARIO, *(n for n in builtin_names() if n != DEFAULT_SCENARIO)]
            self._scenarios = [
                {"name": s.name, "description": s.description, "end_s": s.end_tick / TICKS_PER_S}
                for s in map(load_scenario, names)
            ]
        return JSONResponse(self._scenarios)

    async def arm(self, request: Request) -> Response:
        from crslab.world import WORLD_NAMES

        world = request.query_params.get("world", "none")
        if world not in WORLD_NAMES:
            return JSONResponse({"error": f"no world {world!r}"}, status_code=404)
        if world not in self._arm:
            self._arm[world] = await asyncio.to_thread(arm_shapes, world)
        return JSONResponse(self._arm[world], headers={"Cache-Control": "max-age=3600"})

    async def worlds(self, request: Request) -> Response:
        from crslab.world import WORLD_NAMES, load_world

        described = {"none": "free air (no fixtures)",
                     "contest": "the final project: peg and hole, obstacle, groove, egg on a scale"}
        return JSONResponse([{"name": n, "description": described.get(n, load_world(n).name)}
                             for n in WORLD_NAMES])

    async def download(self, request: Request) -> Response:
        user = self.user_of(request.cookies)
        kind = request.path_params["kind"]
        if user is None:
            return JSONResponse({"error": "log in first"}, status_code=401)
        if kind not in DOWNLOADS:
            return JSONResponse({"error": f"no download {kind!r}"}, status_code=404)
        path = self.sessions.download(request.query_params.get("session", ""), user, DOWNLOADS[kind])
        if path is None:
            return JSONResponse({"error": f"no {kind} of your last run here"}, status_code=404)
        return FileResponse(path, filename=DOWNLOADS[kind], media_type="application/octet-stream")

    async def admin(self, request: Request) -> Response:
        user = self.user_of(request.cookies)
        if user is None or not self.is_admin(user):
            return HTMLResponse("<p>admins only: log in as an admin on the main page</p>", status_code=403)
        rows = [s.describe() for s in self.sessions.all()]
        keys = ["id", "user", "since", "state", "scenario", "runs"]
        body = "".join(
            "<tr>" + "".join(f"<td>{html.escape(str(r[k]))}</td>" for k in keys) + "</tr>" for r in rows
        )
        page = (
            f"<!doctype html><meta charset=utf-8><title>crslab serve: sessions</title>"
            "<link rel=stylesheet href=/static/app.css><body class=admin>"
            f"<h1>Sessions ({len(rows)} of at most "
            f"{self.sessions.limits.max_sessions})</h1><table data-testid=sessions><tr>"
            + "".join(f"<th>{k}</th>" for k in keys)
            + f"</tr>{body}</table>"
        )
        return HTMLResponse(page, headers={"Content-Security-Policy": CSP, "Cache-Control": "no-store"})

    # -- the WebSocket ------------------------------------------------------------------------
    async def websocket(self, ws: WebSocket) -> None:
        user = self.user_of(ws.cookies)
        origin = ws.headers.get("origin")
        if origin is not None and urlparse(origin).netloc != ws.headers.get("host"):
            await ws.close(code=4403, reason="cross-site WebSocket refused")
            return
        if user is None:
            await ws.close(code=4401, reason="log in first")
            return
        await ws.accept()
        try:
            session = await asyncio.to_thread(self.sessions.start, user)
        except LimitError as exc:
            await ws.send_text(json.dumps({"type": "error", "message": str(exc)}))
            await ws.close(code=4429)
            return
        try:
            await self._relay(ws, session)
        finally:
            await asyncio.to_thread(self.sessions.close, session)

    async def _relay(self, ws: WebSocket, session: PageSession) -> None:
        """Hand the page's checked messages to the session process (a running lab's commands to
        its run host) and the messages of both to the page, over the session's pipe as asyncio
        streams (:mod:`crslab.serve.wire`) and the host's (:mod:`crslab.serve.run_hosts`). Every
        message for the page goes through one outbox, in order."""
        reader, writer = await asyncio.open_connection(sock=session.take_socket())
        outbox: asyncio.Queue[tuple[bytes, bytes] | None] = asyncio.Queue()
        hosts = self.sessions.hosts

        def post(tag: bytes, body: bytes) -> None:
            outbox.put_nowait((tag, body))

        def take_pending() -> list[dict]:
            pending, session.pending = session.pending, []
            return pending

        async def to_session(msg: dict) -> None:
            writer.write(wire.pickled(msg))
            await writer.drain()

        async def from_session() -> None:
            try:
                while True:
                    data = await wire.read_frame(reader)
                    tag, body = data[:1], data[1:]
                    if tag == wire.HOST_RUN:  # a prepared run: a host runs it from now on
                        await hosts.hand(session.id, body, post, take_pending)
                    else:
                        post(tag, body)
            except (asyncio.IncompleteReadError, ConnectionError):
                outbox.put_nowait(None)

        async def to_page() -> None:
            try:
                while (item := await outbox.get()) is not None:
                    tag, body = item
                    if tag == wire.RUN_ENDED:
                        session.running = None
                        for msg in take_pending():  # for a run that never started: the session answers
                            await to_session(msg)
                    elif tag == wire.RUN_STARTED:
                        session.running = "run"
                    await ws.send_text(body.decode())
                if session.running is not None:
                    await ws.send_text(SESSION_GONE.decode())
                await ws.close(code=1011)
            except (WebSocketDisconnected, WebSocketDisconnect, ConnectionError):
                pass  # the page had gone first: its going is what ended the session

        reading = asyncio.create_task(from_session())
        pump = asyncio.create_task(to_page())
        await ws.send_text(json.dumps({"type": "hello", "session": session.id, "user": session.user}))
        try:
            while True:
                receive = asyncio.create_task(ws.receive())
                done, _ = await asyncio.wait({receive, pump}, return_when=asyncio.FIRST_COMPLETED)
                if pump in done:
                    receive.cancel()
                    return
                frame = receive.result()
                if frame["type"] == "websocket.disconnect":
                    return
                text = frame.get("text") if frame.get("text") is not None else frame.get("bytes")
                try:
                    msg = parse_message(text or "")
                    self.sessions.admit(session, msg, time.monotonic())
                except (ProtocolError, LimitError) as exc:
                    await ws.send_text(json.dumps({"type": "error", "message": str(exc)}))
                    continue
                if msg["type"] in ("build", "run") and len(hosts.hosts) < hosts.count:
                    # the run hosts start while the lab builds (not while a page loads)
                    asyncio.create_task(hosts.warm())  # noqa: RUF006 - the hosts keep themselves
                if msg["type"] in RUN_COMMANDS and hosts.hosts_run(session.id):
                    await hosts.command(session.id, msg)
                elif msg["type"] in RUN_COMMANDS and session.running == "run":
                    session.pending.append(msg)  # the run is being prepared: its host gets it next
                else:
                    await to_session(msg)
        except (WebSocketDisconnect, ConnectionError):
            return
        finally:
            reading.cancel()
            pump.cancel()
            await hosts.forget(session.id)  # its run (if any) ends now
            writer.close()  # the session process sees the pipe close: it ends itself


def _address(request: Request) -> str:
    """The client's address (behind a trusted proxy, the one it forwarded)."""
    return request.client.host if request.client is not None else "unknown"


def _seconds(wait_s: float) -> str:
    """``3 s``: a wait rounded up to whole seconds."""
    return f"{max(1, int(-(-wait_s // 1)))} s"


def _too_many(text: str, wait_s: float, *, html_page: bool = False) -> Response:
    """A 429 with its one line (JSON for the page's login form, a short page for a token link)."""
    headers = {"Retry-After": str(max(1, int(-(-wait_s // 1)))), "Cache-Control": "no-store"}
    if html_page:
        return HTMLResponse(f"<p>{html.escape(text)}</p>", status_code=429, headers=headers)
    return JSONResponse({"error": text}, status_code=429, headers=headers)


def arm_shapes(world: str = "none") -> dict:
    """The arm's bodies as the MuJoCo model has them, for the page to draw and pose: each body's
    parent, its frame in the parent's (metres; quaternions ``x y z w``), its hinge (axis and anchor
    in its own frame, and which DH angle turns it: ``q``; the peg's wrist, held at minus the sum of
    two, has ``minus_sum``) and its shapes in its frame; in a ``world`` (a built-in's name) its
    fixtures too, which never move (only the arm's links are ``moving``: a hand may drag them), and
    the ``view`` that frames them (:func:`fixtures_view`; None in free air)."""
    from crslab.plant.model import LINK_BODIES
    from crslab.scopes.arm3d import ArmModel
    from crslab.world import load_world
    from crslab.world.scene import WRIST_JOINT

    loaded = load_world(world)
    arm = ArmModel(loaded)
    m = arm.model
    shapes = {b.id: b.shapes for b in arm.bodies}
    out = []
    for b in range(m.nbody):
        q = m.body_quat[b]
        joint = None
        if int(m.body_jntnum[b]) == 1:
            j = int(m.body_jntadr[b])
            joint = {
                "axis": m.jnt_axis[j].tolist(),
                "anchor": m.jnt_pos[j].tolist(),
                "q": int(m.jnt_qposadr[j]),
            }
            if m.joint(j).name == WRIST_JOINT:  # kept vertical: minus the forearm's absolute angle
                joint.update(q=None, minus_sum=[1, 2])
        out.append(
            {
                "name": m.body(b).name or "world",
                "parent": int(m.body_parentid[b]) if b else None,
                "pos": m.body_pos[b].tolist(),
                "quat": [*q[1:].tolist(), float(q[0])],
                "joint": joint,
                "moving": m.body(b).name in LINK_BODIES,
                "shapes": [
                    {
                        "name": s.name,
                        "kind": s.kind,
                        "pos": s.pos,
                        "quat": s.quat_xyzw,
                        "size": s.size,
                        "rgba": s.rgba,
                    }
                    for s in shapes.get(b, [])
                ],
            }
        )
    return {"bodies": out, "view": fixtures_view(loaded)}


VIEW_FOV_DEG = 40.0
"""The page's camera's vertical field of view (arm3d.js's PerspectiveCamera)."""
VIEW_PHI, VIEW_THETA = 1.15, 0.9
"""The page's camera's direction: three.js's spherical angles from its y axis (MuJoCo's z, up)
and about it (arm3d.js turns them into MuJoCo's frame): from above and in front, to the side."""


def fixtures_view(world: object) -> dict | None:
    """Where the page's camera looks from to frame every fixture of ``world`` (a
    :class:`~crslab.world.World`; its solids, the table left out) with the arm's base: the
    middle of their bounding box, at the distance from which the sphere around that box fits the
    field of view (:data:`VIEW_FOV_DEG`, on a square view, 5 % to spare); None in free air.

    >>> from crslab.world import load_world
    >>> fixtures_view(load_world("none")) is None
    True
    """
    import math

    import numpy as np

    from crslab.world.layout_checks import fixture_solids

    solids = [shape for _, shape in fixture_solids(world)]  # type: ignore[arg-type]
    if not solids:
        return None
    corners = np.concatenate([solid_corners(s) for s in solids] + [np.zeros((1, 3))])
    lo, hi = corners.min(axis=0), corners.max(axis=0)
    radius = float(np.linalg.norm(hi - lo)) / 2
    distance = 1.05 * radius / math.sin(math.radians(VIEW_FOV_DEG / 2))
    return {"target": ((lo + hi) / 2).round(4).tolist(), "distance": round(distance, 4), "phi": VIEW_PHI,
            "theta": VIEW_THETA, "fov_deg": VIEW_FOV_DEG}


def solid_corners(shape: object) -> np.ndarray:
    """The corners (rows, m) of a fixture's solid (:mod:`crslab.world.shapes`): a box's eight, or
    those of the box around an upright cylinder."""
    import numpy as np

    from crslab.world.shapes import Box

    z0, z1 = shape.z_range  # type: ignore[attr-defined]
    if isinstance(shape, Box):
        xy = shape.corners_xy()
    else:
        (x, y), r = shape.center_xy, shape.radius  # type: ignore[attr-defined]
        xy = np.array([[x - r, y - r], [x + r, y - r], [x + r, y + r], [x - r, y + r]])
    return np.array([[*p, z] for p in xy for z in (z0, z1)])


def make_app(settings: ServeSettings, sessions: Sessions,
             clock: Callable[[], float] = time.monotonic) -> Starlette:
    """The ASGI application (``clock``: seconds, for the login limits)."""
    server = CrsServer(settings, sessions, clock)
    app = Starlette(
        routes=[
            Route("/", server.index),
            Route("/api/login", server.login, methods=["POST"]),
            Route("/api/logout", server.logout, methods=["POST"]),
            Route("/api/me", server.me),
            Route("/api/template", server.template_text),
            Route("/api/scenarios", server.scenarios),
            Route("/api/arm", server.arm),
            Route("/api/worlds", server.worlds),
            Route("/api/download/{kind}", server.download),
            Route("/admin", server.admin),
            WebSocketRoute("/ws", server.websocket),
            Mount("/static", app=StaticFiles(directory=STATIC), name="static"),
        ]
    )
    app.state.server = server
    return app
