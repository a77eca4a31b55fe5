"""Only a re-export, kept while serve's modules import it from here: serve's recording is
:class:`crslab.sinks.rerun_writer.RecorderSink` (import it from there; this module goes once
nothing imports it)."""

from crslab.sinks.rerun_writer import RecorderSink

__all__ = ["RecorderSink"]
