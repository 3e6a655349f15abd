# Integer arithmetic: the algorithm of mb/bench.mb and pt/bench.pt in Python 3.
def main():
    n = 4000000
    a, q, x, h = 12345, 0, 0, 0
    for i in range(1, n + 1):
        a = (a * 75 + 74) % 65537
        q = q + a // 3
        if q > 1000000000:
            q = q - 1000000000
        x = x ^ (a & 255)
        b = (~a) & 65535
        h = (h + (b | (i & 1023))) % 1000003
    print("A=%d Q=%d X=%d H=%d" % (a, q, x, h))


main()
