-- Integer arithmetic: the algorithm of mb/bench.mb and pt/bench.pt in Lua 5.4.
local n = 4000000
local a, q, x, h = 12345, 0, 0, 0
for i = 1, n do
  a = (a * 75 + 74) % 65537
  q = q + a // 3
  if q > 1000000000 then q = q - 1000000000 end
  x = x ~ (a & 255)
  local b = (~a) & 65535
  h = (h + (b | (i & 1023))) % 1000003
end
print(string.format("A=%d Q=%d X=%d H=%d", a, q, x, h))
