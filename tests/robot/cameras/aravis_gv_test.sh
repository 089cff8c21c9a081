#!/bin/sh
# SPDX-License-Identifier: MIT
# @brief Runs test_aravis_gv_camera against arv-fake-gv-camera-0.8 over real GigE Vision packets:
#        a veth pair with one end in a private network namespace (the fake camera needs an interface
#        with broadcast; loopback is not enough). Needs root; exits 77 (ctest: skipped) with the
#        reason when it cannot set up the namespace.
# usage: aravis_gv_test.sh <test_aravis_gv_camera> [lost packets per 1000, default 5]
set -u
bin=$1
loss=${2:-5}
skip() { echo "SKIPPED: $*"; exit 77; }
[ "$(id -u)" = 0 ] || skip "needs root to create a network namespace"
command -v ip >/dev/null 2>&1 || skip "iproute2 (ip) not installed"
command -v arv-fake-gv-camera-0.8 >/dev/null 2>&1 || skip "arv-fake-gv-camera-0.8 (aravis-tools) not installed"

# Names and a subnet of our own (per process, so parallel runs do not collide).
id=$$
ns="tsgv$id"
host_if="tsgv${id}a"
cam_if="tsgv${id}b"
net="10.213.$((id % 200 + 20))"
cleanup() { ip netns del "$ns" 2>/dev/null; ip link del "$host_if" 2>/dev/null; }
trap cleanup EXIT INT TERM
ip netns add "$ns" 2>/dev/null || skip "cannot create a network namespace (no CAP_SYS_ADMIN?)"
ip link add "$host_if" type veth peer name "$cam_if" || skip "cannot create a veth pair"
ip link set "$cam_if" netns "$ns" || exit 1
ip addr add "$net.1/24" dev "$host_if" && ip link set "$host_if" up || exit 1
ip netns exec "$ns" ip addr add "$net.2/24" dev "$cam_if" || exit 1
ip netns exec "$ns" ip link set "$cam_if" up || exit 1
ip netns exec "$ns" ip link set lo up || exit 1

TELESPHERE_ARAVIS_GV_NETNS="$ns" TELESPHERE_ARAVIS_GV_IFACE="$cam_if" TELESPHERE_ARAVIS_GV_SERIAL="TS$id" \
  TELESPHERE_ARAVIS_GV_LOSS="$loss" "$bin"
