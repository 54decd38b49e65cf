"""The Dask scheduler probe (``campaign.scheduler.check_scheduler``) says which step failed."""

import pytest


def test_a_scheduler_that_accepts_no_connection_in_time_is_said_so(monkeypatch):
    # a peer that never completes the TCP connection (a firewall dropping the packets) was called
    # one that "accepted the connection but did not answer Dask's handshake"
    pytest.importorskip("distributed")
    import asyncio

    from distributed.comm import registry

    from graspcampaign.campaign.scheduler import check_scheduler
    from graspcampaign.errors import UserInputError

    class Silent:
        def get_connector(self):
            return self

        async def connect(self, location, deserialize):
            await asyncio.sleep(60)

    monkeypatch.setattr(registry, "get_backend", lambda scheme: Silent())
    with pytest.raises(UserInputError) as info:
        check_scheduler("tcp://192.0.2.1:8786", 0.3)
    assert str(info.value) == ("runner.address = 'tcp://192.0.2.1:8786': no Dask scheduler answered "
                               "within 0.3 s (nothing accepted the connection); start one (dask "
                               "scheduler) or drop runner.address to run on a local cluster.")


def test_a_refused_connection_stays_refused_when_a_last_retry_is_cut_short(monkeypatch):
    # under load the retry that meets the deadline times out before the refusal arrives; the
    # probe then forgot the refusals before it and said "nothing accepted the connection"
    # (a flaky test_an_unreachable_dask_scheduler_is_one_sentence)
    pytest.importorskip("distributed")
    import asyncio

    from distributed.comm import registry

    from graspcampaign.campaign.scheduler import check_scheduler
    from graspcampaign.errors import UserInputError

    class RefusedThenSlow:
        tries = 0

        def get_connector(self):
            return self

        async def connect(self, location, deserialize):
            RefusedThenSlow.tries += 1
            if RefusedThenSlow.tries == 1:
                raise ConnectionRefusedError(111, "Connection refused")
            await asyncio.sleep(60)

    monkeypatch.setattr(registry, "get_backend", lambda scheme: RefusedThenSlow())
    with pytest.raises(UserInputError) as info:
        check_scheduler("tcp://127.0.0.1:9", 0.3)
    assert "within 0.3 s (OSError)" in str(info.value)
