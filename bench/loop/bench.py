# Counting-loop benchmark: the loop of bench.pt in Python 3.
def main():
    s, t = 0, 0
    for i in range(1, 20000001):
        s = s + 3
        if s > 1000000:
            s = s - 1000000
            t = t + 1
    print(f"S={s} T={t}")


main()
