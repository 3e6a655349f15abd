"""Tests that follow a pattern: the algorithm of bench.lua in Python 3."""


def main():
    t = ph = a = b = c = d = 0
    for i in range(1, 6000001):
        t = 1 - t
        if t == 1:
            a = a + 1
        else:
            b = b + 2
        ph = ph + 1
        if ph == 6:
            ph = 0
        if ph == 0:
            c = c + 3
        if i & 4 != 0:
            d = d + 1
    print("T=%d A=%d B=%d C=%d D=%d" % (t, a, b, c, d))


main()
