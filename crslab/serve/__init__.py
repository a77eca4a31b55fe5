"""``crslab serve``: the lab bench as a web page (docs/serve.md).

``app`` (the Starlette application and its routes), ``auth`` (roster, passwords, cookies,
limits), ``page_messages`` (the WebSocket messages, checked), ``page_sessions`` (one process per
page session, the per-user limits), ``page_process`` (what runs in it: builds, runs, checks),
``stream`` (a run's sink and live control for the page), ``static/`` (the page and its
vendored libraries), ``deploy/`` (a reverse proxy's configuration). The lab templates the page
starts from are ``crslab new``'s (:mod:`crslab.starters`).
"""
