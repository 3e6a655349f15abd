# Branches and counters: the algorithm of mb/bench.mb and pt/bench.pt in Python 3.
def main():
    p = a = b = c = d = 0
    for i in range(1, 8000001):
        p = p + 7
        if p >= 100:
            p = p - 100
        if p < 25:
            a = a + 1
        else:
            if p < 50:
                b = b + 1
            else:
                if p < 75 or p == 99:
                    c = c + 1
                else:
                    d = d + 2
    print("P=%d A=%d B=%d C=%d D=%d" % (p, a, b, c, d))


main()
