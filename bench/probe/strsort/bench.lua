local w = {}
local x = 7
for r = 1, 40 do
for i = 1, 300 do
  x = (x * 1103 + 12345) % 65536
  w[i] = string.char(65 + x % 26) .. string.char(65 + (x // 26) % 26) .. string.char(65 + (x // 676) % 26)
end
for i = 2, 300 do
  local t = w[i]; local j = i - 1
  while j > 0 and w[j] > t do w[j + 1] = w[j]; j = j - 1 end
  w[j + 1] = t
end
end
local c = 0
for i = 1, 300 do c = c + string.byte(w[i]) * i + string.byte(w[i], 3) end
print(c)
