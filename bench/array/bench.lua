-- Arrays: the algorithm of bench.mb in Lua 5.4 (tables indexed from 1: index + 1).
local flag, ring = {}, {}
for i = 1, 20001 do flag[i] = 0 end
for i = 1, 16 do ring[i] = 0.0 end
local n = 20000
for r = 1, 25 do
  for i = 2, n do flag[i + 1] = 1 end
  for i = 2, 141 do
    if flag[i + 1] ~= 0 then
      for j = i * i, n, i do flag[j + 1] = 0 end
    end
  end
end
local primes = 0
for i = 2, n do primes = primes + flag[i + 1] end
local s, x = 0.0, 0.0
for i = 1, 1000000 do
  local k = i & 15
  x = x * 0.5 + (i % 7)
  s = s - ring[k + 1] + x
  ring[k + 1] = x
end
print(string.format("PRIMES=%d AVG=%.9f", primes, s / 16))
