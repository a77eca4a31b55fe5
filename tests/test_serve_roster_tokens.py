"""A roster's token is compared whole: a token that shares its first characters with the roster's
(a guess, or a classmate's token from the same generator prefix) does not log in."""

import secrets

from crslab.serve.auth import hash_password, verify_secret


def test_a_token_is_compared_on_every_character():
    token = "Zq3x9LmA" + secrets.token_urlsafe(16)
    secret = f"token:{token}"
    assert verify_secret(secret, token)
    assert not verify_secret(secret, token[:8])  # its first 8 characters only
    assert not verify_secret(secret, token[:8] + "x" * (len(token) - 8))
    assert not verify_secret(secret, token[:-1] + ("a" if token[-1] != "a" else "b"))  # the last one differs
    assert not verify_secret(secret, token + "x")


def test_a_password_is_compared_on_every_character():
    secret = hash_password("correct horse battery", iterations=1000)
    assert verify_secret(secret, "correct horse battery")
    assert not verify_secret(secret, "correct horse batterx")
    assert not verify_secret(secret, "correct ")
