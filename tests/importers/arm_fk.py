#!/usr/bin/env python3
"""Independent forward kinematics of a RoverLab arm file (classic DH), for tests.

usage: arm_fk.py ARM.json < angles   (one line of joint angles in rad per configuration)
prints the tool point's base-frame z (m) per line, with 17 significant digits.
Written from the DH definition (Craig 1989, Eq. 3.6 transposed to the classic
convention: Rz(theta) Tz(d) Tx(a) Rx(alpha)), not from RoverLab's code.
"""
import json
import math
import sys


def matmul(p, q):
    return [[sum(p[i][k] * q[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def dh(theta, d, a, alpha):
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    rz = [[ct, -st, 0, 0], [st, ct, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
    tz = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, d], [0, 0, 0, 1]]
    tx = [[1, 0, 0, a], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
    rx = [[1, 0, 0, 0], [0, ca, -sa, 0], [0, sa, ca, 0], [0, 0, 0, 1]]
    return matmul(matmul(matmul(rz, tz), tx), rx)


def main():
    arm = json.load(open(sys.argv[1]))
    tool = arm.get("tool_m", [0.0, 0.0, 0.0]) + [1.0]
    for line in sys.stdin:
        q = [float(v) for v in line.split()]
        if not q:
            continue
        t = [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]
        for link, angle in zip(arm["links"], q):
            t = matmul(t, dh(link["theta"] + angle, link["d"], link["a"], link["alpha"]))
        print(repr(sum(t[2][k] * tool[k] for k in range(4))))


if __name__ == "__main__":
    main()
