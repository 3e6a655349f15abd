# Strings: the algorithm of bench.mb in Python 3.
def main():
    n = 300000
    l = t = k = h = 0
    for i in range(1, n + 1):
        c = chr(65 + i % 26) + "-" + str(1000 + i % 9000) + "/" + "XYZW"[:1 + i % 4]
        l += len(c)
        p = c.find("/") + 1
        t += int(float(c[2:p - 1]))
        if "7" in c:
            k += 1
        h = (h * 31 + ord(c[-1])) % 1000003
    print(f"L={l} T={t} K={k} H={h}")


main()
