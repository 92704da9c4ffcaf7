"""A local Ray listens on the loopback address only: nothing it opens is reachable from the network."""

from __future__ import annotations

import ipaddress

import pytest

psutil = pytest.importorskip("psutil", reason="psutil comes with ray[rllib]")


def ray_processes() -> list:
    """This process and everything it started (Ray's GCS, raylet, agents and workers)."""
    me = psutil.Process()
    return [me, *me.children(recursive=True)]


def listening(pids: set[int]) -> list[tuple[int, str, int]]:
    """``(pid, address, port)`` of each listening TCP socket those processes hold."""
    out = []
    for pid in pids:
        try:
            conns = psutil.Process(pid).net_connections(kind="tcp")
        except (psutil.NoSuchProcess, psutil.AccessDenied):
            continue
        out += [(pid, c.laddr.ip, c.laddr.port) for c in conns if c.status == psutil.CONN_LISTEN]
    return out


def loopback(ip: str) -> bool:
    """127.0.0.1, ::1 or 127.0.0.1 as an IPv6 socket shows it (``::ffff:127.0.0.1``); not ``::`` or 0.0.0.0."""
    address = ipaddress.ip_address(ip)
    return (getattr(address, "ipv4_mapped", None) or address).is_loopback


def test_the_local_node_address_stays_loopback_where_ray_would_turn_it_into_the_network_address(monkeypatch):
    """Ray on Linux resolves 127.0.0.1 to the machine's reachable address when a node starts;
    ``init_local_ray`` keeps it 127.0.0.1 (the address Ray's servers bind to), and only then."""
    import ray
    from ray._private import ray_constants, services

    from babyrobot_marl.integrations.rllib import init_local_ray

    seen = {}

    def fake_init(**kwargs):
        seen.update(kwargs, resolved=services.resolve_ip_for_localhost(kwargs["_node_ip_address"]))

    monkeypatch.setattr(ray, "init", fake_init)
    cluster = ray_constants.ENABLE_RAY_CLUSTER
    init_local_ray(2, log_to_driver=False)
    assert seen["resolved"] == "127.0.0.1" and seen["include_dashboard"] is False and seen["num_cpus"] == 2
    assert seen["log_to_driver"] is False and ray_constants.ENABLE_RAY_CLUSTER is cluster  # put back


def test_every_port_a_local_ray_opens_is_bound_to_the_loopback_address(ray_local):
    @ray_local.remote
    def ping() -> int:
        return 1

    assert ray_local.get(ping.remote()) == 1  # a worker started: its ports are open too
    ports = listening({p.pid for p in ray_processes()})
    assert len(ports) >= 3, ports  # the GCS, the raylet and a worker at least: the test sees Ray's sockets
    exposed = [p for p in ports if not loopback(p[1])]
    assert exposed == [], f"listening beyond 127.0.0.1: {exposed}"
    assert ray_local.util.get_node_ip_address() == "127.0.0.1"
