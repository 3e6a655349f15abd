# Subroutine calls: the algorithm of mb/bench.mb and pt/bench.pt in Python 3 (globals, as the
# BASIC subroutine shares the program's variables).
S = 0
K = 0


def step1(x):
    global S, K
    S = S + x % 13
    if S > 100000:
        S = S - 100000
        K = K + 1


def main():
    for i in range(1, 3000001):
        step1(i)
    print("S=%d K=%d" % (S, K))


main()
