# Arrays: the algorithm of bench.mb in Python 3.
def main():
    n = 20000
    flag = [0] * (n + 1)
    ring = [0.0] * 16
    for r in range(25):
        for i in range(2, n + 1):
            flag[i] = 1
        for i in range(2, 142):
            if flag[i]:
                for j in range(i * i, n + 1, i):
                    flag[j] = 0
    primes = 0
    for i in range(2, n + 1):
        primes += flag[i]
    s = x = 0.0
    for i in range(1, 1000001):
        k = i & 15
        x = x * 0.5 + (i % 7)
        s = s - ring[k] + x
        ring[k] = x
    print("PRIMES=%d AVG=%.9f" % (primes, s / 16))


main()
