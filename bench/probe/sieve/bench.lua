local n = 30000
local f = {}
local t = 0
for r = 1, 60 do
local c = 0
for i = 0, n do f[i] = 0 end
for i = 2, n do
  if f[i] == 0 then
    c = c + 1
    for j = i + i, n, i do f[j] = 1 end
  end
end
t = t + c
end
print(t)
