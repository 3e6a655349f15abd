# Real-valued filters: the algorithm of bench.mb in Python 3.
def main():
    b0, b1, b2, a1, a2 = 0.0675, 0.135, 0.0675, -1.143, 0.413
    u1 = u2 = y1 = y2 = pk = hp = 0.0
    for i in range(1, 4000001):
        if (i & 63) < 32:
            u = 1.0
        else:
            u = -1.0
        y = b0 * u + b1 * u1 + b2 * u2 - a1 * y1 - a2 * y2
        hp = 0.95 * (hp + y - y1)
        u2 = u1
        u1 = u
        y2 = y1
        y1 = y
        if y > pk:
            pk = y
    print("Y=%.9f PK=%.9f HP=%.9f" % (y1, pk, hp))


main()
