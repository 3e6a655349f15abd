# The unseen benchmark of bench.mb in Python 3.
def main():
    n = 10000000
    c, f = 0, 0.0
    for i in range(1, n + 1):
        m = i % 7
        f = f * 0.875 + m * 0.125
        if f > 3.5:
            c += 1
    print("C=%d F=%.6f" % (c, f))


main()
