"""The nginx configuration crslab ships for N replicas behind a reverse proxy (crslab/serve/deploy/)
is one nginx accepts: ``nginx -t`` on the file itself, with a throwaway certificate beside it."""

import shutil
import subprocess
from pathlib import Path

import pytest

import crslab.serve

CONF = Path(crslab.serve.__file__).parent / "deploy" / "nginx.conf"


@pytest.mark.requires("nginx", "openssl")
def test_nginx_accepts_the_shipped_configuration(tmp_path):
    conf = tmp_path / "nginx.conf"
    shutil.copyfile(CONF, conf)  # the file as shipped, byte for byte
    (tmp_path / "tls").mkdir()
    subprocess.run(
        [
            "openssl",
            "req",
            "-x509",
            "-newkey",
            "rsa:2048",
            "-nodes",
            "-days",
            "1",
            "-subj",
            "/CN=localhost",
            "-keyout",
            str(tmp_path / "tls" / "privkey.pem"),
            "-out",
            str(tmp_path / "tls" / "fullchain.pem"),
        ],
        check=True,
        capture_output=True,
    )
    r = nginx_test(conf, tmp_path)
    assert r.returncode == 0, r.stderr
    assert "syntax is ok" in r.stderr and "test is successful" in r.stderr


def nginx_test(conf: Path, folder: Path) -> subprocess.CompletedProcess:
    """``nginx -t`` on ``conf``, its pid and error log in ``folder``."""
    return subprocess.run(["nginx", "-t", "-p", str(folder), "-c", str(conf), "-g",
                           f"pid {folder}/nginx.pid; error_log {folder}/error.log;"],
                          capture_output=True, text=True)


@pytest.mark.requires("nginx")
def test_nginx_would_notice_a_broken_configuration(tmp_path):
    conf = tmp_path / "nginx.conf"
    conf.write_text(CONF.read_text().replace("hash $cookie_crslab_user consistent;", "hash;"))
    r = nginx_test(conf, tmp_path)
    assert r.returncode != 0 and "hash" in r.stderr
