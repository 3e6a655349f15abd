# Kernel calls: the algorithm of mb/bench.mb and pt/bench.pt in Python 3; the kernel is a list
# of axes and two functions reading it.
AXES = [None, {"pos": 0.0, "status": 0}]


def pos(n):
    return AXES[n]["pos"]


def statussv(n):
    return AXES[n]["status"]


def main():
    s, g = 0.0, 0
    for i in range(1, 2000001):
        s = s + pos(1) + 0.5
        if statussv(1) == 0:
            g = g + 1
    print("S=%.1f G=%d" % (s, g))


main()
