-- Subroutine calls: the algorithm of mb/bench.mb and pt/bench.pt in Lua 5.4 (globals, as
-- the BASIC subroutine shares the program's variables).
S, K = 0, 0
local function step1(x)
  S = S + x % 13
  if S > 100000 then
    S = S - 100000
    K = K + 1
  end
end
for i = 1, 3000000 do
  step1(i)
end
print(string.format("S=%d K=%d", S, K))
