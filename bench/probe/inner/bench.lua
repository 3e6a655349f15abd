local s, f, c = 0, 0.0, 0
local function sub()
  if f > 50 then c = c + 1 end
end
for i = 1, 200000 do
  for j = 1, 5 do
    s = (s + i * j) % 1000003
  end
  f = f * 0.9 + (s % 100) * 0.1
  sub()
end
print(s, string.format("%.7g", f), c)
