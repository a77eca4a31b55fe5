"""Builds of crslab's own C are shared by content through the cache, by every checkout of the
user: their debug information names crslab's C folder alike from all of them (``/crslab/csrc``),
never the checkout that happened to build first, and gdb is told where this checkout's folder is."""


import pytest

from crslab import resources
from crslab.debug.gdb_commands import setup_script
from crslab.lab.firmware import DEBUG_INFO_CSRC


@pytest.mark.requires("cc")
def test_the_native_boards_debug_build_names_no_checkout(tmp_path):
    from crslab.lab.build import _board_objects
    from crslab.lab.compiler import find_compiler

    objects = _board_objects(find_compiler(), False, tmp_path, debug=True)
    csrc = str(resources.path("csrc")).encode()
    named = [o.name for o in objects if csrc in o.read_bytes()]
    assert not named, f"{named} name this checkout's {csrc.decode()}"
    assert any(DEBUG_INFO_CSRC.encode() + b"/board" in o.read_bytes() for o in objects)


def test_gdb_is_told_where_this_checkouts_c_folder_is():
    csrc = resources.path("csrc")
    script = setup_script(csrc).splitlines()
    assert f'set substitute-path {DEBUG_INFO_CSRC} "{csrc}"' in script


def test_the_firmware_objects_name_no_checkout(tmp_path):
    from crslab.lab.build import content_digest
    from crslab.lab.firmware import firmware_objects

    objects = firmware_objects(tmp_path, content_digest)
    csrc = str(resources.path("csrc")).encode()
    assert not [o.name for o in objects if csrc in o.read_bytes()]
    assert any(DEBUG_INFO_CSRC.encode() in o.read_bytes() for o in objects)
